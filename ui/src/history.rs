//! The last seconds of frame and GPU pass times, for the timings plot.

use std::collections::VecDeque;

use render_core::gpu::{PassTiming, summed_by_label};

/// One recorded frame.
#[derive(Clone, Debug, PartialEq)]
pub struct TimingSample {
    pub time_s: f64,
    pub frame_ms: f64,
    /// The frame's passes, summed by label; the steps timed inside a pass are left out.
    pub gpu: Vec<PassTiming>,
}

/// A bounded window of [`TimingSample`]s: samples older than [`TimingHistory::WINDOW_S`] behind
/// the newest are dropped, and never more than [`TimingHistory::MAX_SAMPLES`] are kept.
#[derive(Clone, Debug, Default)]
pub struct TimingHistory {
    samples: VecDeque<TimingSample>,
}

impl TimingHistory {
    /// How far back the history reaches, seconds.
    pub const WINDOW_S: f64 = 10.0;
    /// Hard cap, so a very high frame rate or a clock that stands still cannot grow it.
    pub const MAX_SAMPLES: usize = 4096;

    /// Appends one frame. A time before the newest sample (a restarted clock) starts over.
    pub fn push(&mut self, time_s: f64, frame_ms: f64, gpu: &[PassTiming]) {
        if !time_s.is_finite() {
            return;
        }
        if self.samples.back().is_some_and(|s| time_s < s.time_s) {
            self.samples.clear();
        }
        self.samples.push_back(TimingSample {
            time_s,
            frame_ms,
            gpu: summed_by_label(gpu)
                .into_iter()
                .filter(|p| p.depth == 0)
                .collect(),
        });
        while self.samples.len() > Self::MAX_SAMPLES
            || self
                .samples
                .front()
                .is_some_and(|s| s.time_s < time_s - Self::WINDOW_S)
        {
            self.samples.pop_front();
        }
    }

    pub fn len(&self) -> usize {
        self.samples.len()
    }

    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    pub fn samples(&self) -> impl ExactSizeIterator<Item = &TimingSample> {
        self.samples.iter()
    }

    pub fn newest(&self) -> Option<&TimingSample> {
        self.samples.back()
    }

    /// Time span from the oldest to the newest sample, seconds.
    pub fn span_s(&self) -> f64 {
        match (self.samples.front(), self.samples.back()) {
            (Some(a), Some(b)) => b.time_s - a.time_s,
            _ => 0.0,
        }
    }

    /// Frame times as `[seconds relative to the newest sample (<= 0), ms]`.
    pub fn frame_series(&self) -> Vec<[f64; 2]> {
        let now = self.newest().map_or(0.0, |s| s.time_s);
        self.samples
            .iter()
            .map(|s| [s.time_s - now, s.frame_ms])
            .collect()
    }

    /// One series per GPU pass label, in order of first appearance, like [`Self::frame_series`].
    /// Frames without a time for a pass leave no point in its series.
    pub fn pass_series(&self) -> Vec<(String, Vec<[f64; 2]>)> {
        let now = self.newest().map_or(0.0, |s| s.time_s);
        let mut series: Vec<(String, Vec<[f64; 2]>)> = Vec::new();
        for sample in &self.samples {
            for pass in &sample.gpu {
                let point = [sample.time_s - now, pass.gpu_ms];
                match series.iter_mut().find(|(label, _)| *label == pass.label) {
                    Some((_, points)) => points.push(point),
                    None => series.push((pass.label.clone(), vec![point])),
                }
            }
        }
        series
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pass(label: &str, gpu_ms: f64) -> PassTiming {
        PassTiming {
            label: label.to_owned(),
            gpu_ms,
            depth: 0,
        }
    }

    #[test]
    fn drops_samples_older_than_the_window() {
        let mut h = TimingHistory::default();
        for i in 0..=300 {
            h.push(f64::from(i) * 0.1, 16.0, &[]);
        }
        // Newest at 30 s: samples from 20 s on remain.
        assert_eq!(h.len(), 101);
        assert!((h.span_s() - TimingHistory::WINDOW_S).abs() < 1e-9);
        assert!(
            h.frame_series()
                .iter()
                .all(|p| p[0] <= 0.0 && p[0] >= -10.0)
        );
    }

    #[test]
    fn caps_samples_when_the_clock_stands_still() {
        let mut h = TimingHistory::default();
        for _ in 0..TimingHistory::MAX_SAMPLES + 100 {
            h.push(1.0, 1.0, &[]);
        }
        assert_eq!(h.len(), TimingHistory::MAX_SAMPLES);
    }

    #[test]
    fn restarted_clock_starts_over_and_nan_is_ignored() {
        let mut h = TimingHistory::default();
        h.push(5.0, 1.0, &[]);
        h.push(6.0, 1.0, &[]);
        h.push(f64::NAN, 1.0, &[]);
        assert_eq!(h.len(), 2);
        h.push(0.5, 2.0, &[]);
        assert_eq!(h.len(), 1);
        assert_eq!(h.newest().map(|s| s.frame_ms), Some(2.0));
    }

    #[test]
    fn pass_series_follow_first_appearance_and_skip_missing_frames() {
        let mut h = TimingHistory::default();
        h.push(0.0, 10.0, &[pass("shadow map", 1.0)]);
        h.push(1.0, 11.0, &[]);
        h.push(2.0, 12.0, &[pass("shading", 3.0), pass("shadow map", 2.0)]);
        let series = h.pass_series();
        let labels: Vec<_> = series.iter().map(|(l, _)| l.as_str()).collect();
        assert_eq!(labels, ["shadow map", "shading"]);
        assert_eq!(series[0].1, vec![[-2.0, 1.0], [0.0, 2.0]]);
        assert_eq!(series[1].1, vec![[0.0, 3.0]]);
        assert_eq!(
            h.frame_series(),
            vec![[-2.0, 10.0], [-1.0, 11.0], [0.0, 12.0]]
        );
    }
}
