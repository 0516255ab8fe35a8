//! What the GPU can do to a frame that is nobody's bug: run out of memory, refuse a resource
//! beyond its limits, or be lost (a driver reset, a removed card). Each becomes a [`GpuFault`]
//! the frame reports instead of a wgpu panic: the window recovers from it (the previous
//! settings, or a new device), a headless command exits with its message.

use std::sync::{Arc, Mutex, PoisonError};

/// A GPU failure a frame reports; its message says what to change.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum GpuFault {
    /// The device could not allocate a resource.
    #[error(
        "GPU memory exhausted: {what}{} and the GPU could not allocate it; {remedy}",
        if *asked > 0 { format!(" asked for {}", bytes_text(*asked)) } else { String::new() }
    )]
    OutOfMemory {
        what: String,
        asked: u64,
        remedy: String,
    },
    /// A resource beyond the device's limits (a texture wider than its largest, too many layers).
    #[error(
        "{what}{}: beyond this GPU's limits ({detail}); {remedy}",
        if *asked > 0 { format!(" ({})", bytes_text(*asked)) } else { String::new() }
    )]
    OverLimit {
        what: String,
        asked: u64,
        detail: String,
        remedy: String,
    },
    /// The device is gone: a driver reset, a removed GPU, or `Device::destroy`.
    #[error("the GPU device was lost ({reason}): {message}")]
    DeviceLost { reason: String, message: String },
}

impl GpuFault {
    pub fn is_device_lost(&self) -> bool {
        matches!(self, Self::DeviceLost { .. })
    }
}

/// Bytes as a person reads them: "12.0 GiB", "64.0 MiB", "512 B".
pub fn bytes_text(bytes: u64) -> String {
    const KIB: f64 = 1024.0;
    let b = bytes as f64;
    if b >= KIB * KIB * KIB {
        format!("{:.1} GiB", b / (KIB * KIB * KIB))
    } else if b >= KIB * KIB {
        format!("{:.1} MiB", b / (KIB * KIB))
    } else if b >= KIB {
        format!("{:.1} KiB", b / KIB)
    } else {
        format!("{bytes} B")
    }
}

/// What an allocation is for, to name it when it fails.
#[derive(Clone, Debug)]
pub struct Asked {
    /// "the many lights' maps: 192 layers of 4096 x 4096 (`Depth32Float`)".
    pub what: String,
    /// What the user can change: "fewer lights (--lights) or smaller maps (--shadow-res)".
    pub remedy: &'static str,
}

/// The device's faults so far: the loss is kept (a lost device stays lost), an allocation's
/// fault until a frame takes it. Shared by the context's clones and wgpu's callbacks.
#[derive(Debug, Default)]
pub(super) struct Faults {
    lost: Option<GpuFault>,
    pending: Option<GpuFault>,
}

pub(super) type SharedFaults = Arc<Mutex<Faults>>;

fn lock(faults: &SharedFaults) -> std::sync::MutexGuard<'_, Faults> {
    faults.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Records a fault; the first one that no frame has taken yet stays (it is the cause).
pub(super) fn record(faults: &SharedFaults, fault: GpuFault) {
    let mut faults = lock(faults);
    if fault.is_device_lost() {
        faults.lost.get_or_insert(fault);
    } else {
        faults.pending.get_or_insert(fault);
    }
}

/// The loss, if the device is lost, else the pending fault (taken).
pub(super) fn take(faults: &SharedFaults) -> Option<GpuFault> {
    let mut faults = lock(faults);
    faults.lost.clone().or_else(|| faults.pending.take())
}

/// Whether an error now is the consequence of a fault already known (a resource left invalid
/// by a failed allocation, a call on a lost device), not a bug of its own.
pub(super) fn explained(faults: &SharedFaults) -> bool {
    let faults = lock(faults);
    faults.lost.is_some() || faults.pending.is_some()
}

/// Installs wgpu's callbacks on `device`: its loss and any allocation that runs out of memory
/// outside [`super::GpuContext::allocate`] are recorded; a validation error stays a panic (it
/// is a bug, and the tests should see it) unless a recorded fault explains it.
pub(super) fn watch(device: &wgpu::Device, faults: &SharedFaults) {
    let on_lost = Arc::clone(faults);
    device.set_device_lost_callback(move |reason, message| {
        let reason = match reason {
            wgpu::DeviceLostReason::Destroyed => "destroyed",
            wgpu::DeviceLostReason::Unknown => "driver reset or GPU removed",
        };
        record(
            &on_lost,
            GpuFault::DeviceLost {
                reason: reason.to_owned(),
                message: if message.is_empty() {
                    "no message from the driver".to_owned()
                } else {
                    message
                },
            },
        );
    });
    let on_error = Arc::clone(faults);
    device.on_uncaptured_error(Arc::new(move |error| match error {
        wgpu::Error::OutOfMemory { source } => record(
            &on_error,
            GpuFault::OutOfMemory {
                what: source.to_string(),
                asked: 0,
                remedy: "lower the resolution, the number of lights or the pages of the pool"
                    .to_owned(),
            },
        ),
        other if explained(&on_error) => {
            log::debug!("after a GPU fault: {other}");
        }
        other => panic!("wgpu error: {other}"),
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_in_binary_units() {
        assert_eq!(bytes_text(512), "512 B");
        assert_eq!(bytes_text(64 * 1024 * 1024), "64.0 MiB");
        assert_eq!(bytes_text(192 * 4096 * 4096 * 4), "12.0 GiB");
    }

    #[test]
    fn a_lost_device_stays_lost_and_an_allocation_fault_is_taken_once() {
        let faults = SharedFaults::default();
        assert_eq!(take(&faults), None);
        let oom = GpuFault::OutOfMemory {
            what: "a map".into(),
            asked: 1 << 30,
            remedy: "smaller".into(),
        };
        record(&faults, oom.clone());
        // A second fault behind the first does not replace the cause.
        record(
            &faults,
            GpuFault::OutOfMemory {
                what: "another".into(),
                asked: 1,
                remedy: String::new(),
            },
        );
        assert!(explained(&faults));
        assert_eq!(take(&faults), Some(oom));
        assert_eq!(take(&faults), None);
        let lost = GpuFault::DeviceLost {
            reason: "destroyed".into(),
            message: "gone".into(),
        };
        record(&faults, lost.clone());
        assert_eq!(take(&faults), Some(lost.clone()));
        assert_eq!(take(&faults), Some(lost));
    }
}
