//! Scenes load on a worker thread: the window keeps drawing the current scene, the panel shows
//! what is loading and for how long, and the new scene replaces the old one when it is ready.

use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::scene_source::{LoadOptions, Loaded, load_scene};

/// One scene being loaded.
pub(super) struct Loading {
    pub spec: String,
    /// What it loads with; the window's own once the scene is in.
    pub options: LoadOptions,
    started: Instant,
    receiver: mpsc::Receiver<anyhow::Result<Loaded>>,
}

impl Loading {
    pub fn start(spec: &str, options: LoadOptions) -> Self {
        let (sender, receiver) = mpsc::channel();
        let owned = spec.to_owned();
        std::thread::spawn(move || {
            // The window may have started another load meanwhile; then nobody waits for this.
            let _ = sender.send(load_scene(&owned, &options));
        });
        Self {
            spec: spec.to_owned(),
            options,
            started: Instant::now(),
            receiver,
        }
    }

    /// The result once the load has finished.
    pub fn poll(&self) -> Option<anyhow::Result<Loaded>> {
        match self.receiver.try_recv() {
            Ok(result) => Some(result),
            Err(mpsc::TryRecvError::Empty) => None,
            Err(mpsc::TryRecvError::Disconnected) => Some(Err(anyhow::anyhow!(
                "the loading thread stopped without an answer"
            ))),
        }
    }

    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// What the panel says while it loads.
    pub fn progress(&self) -> String {
        format!(
            "Loading {} … {:.1} s (the current scene stays until it is ready)",
            self.spec,
            self.elapsed().as_secs_f32()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn finished(loading: &Loading) -> anyhow::Result<Loaded> {
        let deadline = Instant::now() + Duration::from_mins(2);
        loop {
            if let Some(result) = loading.poll() {
                return result;
            }
            assert!(Instant::now() < deadline, "{} did not finish", loading.spec);
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    #[test]
    fn a_scene_loads_off_the_calling_thread() {
        let loading = Loading::start("builtin:boxes", LoadOptions::default());
        // The call returns at once; the answer comes later.
        assert!(loading.progress().starts_with("Loading builtin:boxes"));
        let loaded = finished(&loading).expect("boxes load");
        assert_eq!(loaded.scene.name, "builtin:boxes");
    }

    #[test]
    fn a_failed_load_comes_back_as_its_error() {
        let loading = Loading::start("no/such/scene.glb", LoadOptions::default());
        let message = format!("{:#}", finished(&loading).err().expect("an error"));
        assert!(message.contains("no/such/scene.glb"), "{message}");
    }
}
