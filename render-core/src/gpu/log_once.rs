//! Per-frame failures are logged once, not every frame: a message is logged when it first
//! appears or changes, and again after it has cleared and come back.

/// The last message logged. Long-lived, one per source of failures.
#[derive(Debug, Default)]
pub struct LogOnce {
    last: Option<String>,
}

impl LogOnce {
    /// Logs `message` as a warning unless it was the last one logged.
    pub fn warn(&mut self, message: &str) {
        if self.last.as_deref() != Some(message) {
            log::warn!("{message}");
            self.last = Some(message.to_owned());
        }
    }

    /// The failure has gone: the next one is logged again.
    pub fn clear(&mut self) {
        self.last = None;
    }
}
