//! `--frame-log FILE`: a CSV line per frame the window presents, where its time went and
//! whether it waited for the GPU. The window never should: its timings and counts come back
//! a frame or more later, and only a screenshot reads a picture back at once.

use std::fs::File;
use std::io::{BufWriter, Write as _};
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use render_core::frame::FrameReport;

use super::Running;

/// One presented frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameLine {
    pub frame: u64,
    /// Wall time since the frame before began, ms.
    pub since_last_ms: f64,
    /// The CPU's work before painting: egui's panel and the view's frame recorded and
    /// submitted, ms.
    pub update_ms: f64,
    /// Waiting for the window's next surface texture (the swapchain's pace), ms.
    pub acquire_ms: f64,
    /// Painting the window and presenting it, the acquire included, ms.
    pub paint_ms: f64,
    /// Submitting the window's egui pass, and presenting it, ms: where a software adapter's
    /// driver runs the frame's commands (lavapipe's queue executes them as the CPU's own work).
    pub submit_ms: f64,
    pub present_ms: f64,
    /// Times the CPU waited for the GPU to finish ([`render_core::gpu::GpuContext::waits`]).
    pub gpu_waits: u64,
    /// How many frames older than this one the GPU times shown with it are (none yet: `None`).
    pub gpu_times_behind: Option<u64>,
    /// The GPU frame time those times add up to, ms.
    pub gpu_frame_ms: Option<f64>,
    /// A screenshot was read back this frame (it waits for the GPU, as asked).
    pub screenshot: bool,
    pub objects: usize,
}

/// The open log.
pub struct FrameLog {
    file: PathBuf,
    out: Option<BufWriter<File>>,
}

const HEADER: &str = "frame,since_last_ms,update_ms,acquire_ms,paint_ms,submit_ms,present_ms,gpu_waits,\
                      gpu_times_behind,gpu_frame_ms,screenshot,objects";

impl FrameLog {
    /// Creates `file` with its header; an error names the file.
    pub fn create(file: &Path) -> anyhow::Result<Self> {
        let mut out = BufWriter::new(
            File::create(file)
                .with_context(|| format!("--frame-log: creating {}", file.display()))?,
        );
        writeln!(out, "{HEADER}").with_context(|| format!("writing {}", file.display()))?;
        Ok(Self {
            file: file.to_owned(),
            out: Some(out),
        })
    }

    /// Appends `line`; after a failed write the log says so once and stops.
    pub fn record(&mut self, line: &FrameLine) {
        let Some(out) = &mut self.out else {
            return;
        };
        let opt = |v: Option<String>| v.unwrap_or_default();
        let written = writeln!(
            out,
            "{},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{},{},{},{},{}",
            line.frame,
            line.since_last_ms,
            line.update_ms,
            line.acquire_ms,
            line.paint_ms,
            line.submit_ms,
            line.present_ms,
            line.gpu_waits,
            opt(line.gpu_times_behind.map(|b| b.to_string())),
            opt(line.gpu_frame_ms.map(|ms| format!("{ms:.2}"))),
            u8::from(line.screenshot),
            line.objects,
        )
        .and_then(|()| out.flush());
        if let Err(e) = written {
            log::error!(
                "--frame-log: writing {}: {e}; no more lines",
                self.file.display()
            );
            self.out = None;
        }
    }
}

impl Running {
    /// The frame's line of `--frame-log`: its times, and how often it waited for the GPU since
    /// `waits_before`.
    pub(super) fn log_frame(
        &mut self,
        (dt_s, update_ms, paint_ms): (f32, f64, f64),
        waits_before: u64,
        screenshot: bool,
    ) {
        let Some(log) = &mut self.frame_log else {
            return;
        };
        let report = self.last_report.as_ref();
        log.record(&FrameLine {
            frame: self.frames_presented,
            since_last_ms: f64::from(dt_s) * 1000.0,
            update_ms,
            acquire_ms: self.surface.last_acquire_ms,
            paint_ms,
            submit_ms: self.surface.last_submit_ms,
            present_ms: self.surface.last_present_ms,
            gpu_waits: self.ctx.waits() - waits_before,
            gpu_times_behind: report.and_then(|r| {
                r.gpu_frame_index
                    .map(|gpu| r.frame_index.saturating_sub(gpu))
            }),
            gpu_frame_ms: report.and_then(FrameReport::gpu_total_ms),
            screenshot,
            objects: self.facts.objects,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_per_frame_under_its_header() {
        let file =
            std::env::temp_dir().join(format!("shadowlab-frames-{}.csv", std::process::id()));
        let mut log = FrameLog::create(&file).unwrap();
        let line = FrameLine {
            frame: 3,
            since_last_ms: 16.7,
            update_ms: 4.0,
            acquire_ms: 0.5,
            paint_ms: 2.25,
            submit_ms: 0.75,
            present_ms: 1.0,
            gpu_waits: 0,
            gpu_times_behind: Some(2),
            gpu_frame_ms: None,
            screenshot: false,
            objects: 1_000,
        };
        log.record(&line);
        let text = std::fs::read_to_string(&file).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], HEADER);
        assert_eq!(lines[1], "3,16.70,4.00,0.50,2.25,0.75,1.00,0,2,,0,1000");
        assert_eq!(lines[0].split(',').count(), lines[1].split(',').count());
        assert!(FrameLog::create(Path::new("/nonexistent-dir/x.csv")).is_err());
    }
}
