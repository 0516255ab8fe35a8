//! What comes back from GPU culling, a frame or two late: per view, the stages' counts and
//! each object's outcome, labelled with the frame and method they belong to.

use std::collections::VecDeque;

use crate::culling::codes::{COUNTER_SLOTS, SLOT_RENDERED, SLOT_TRIANGLES, outcome_from_code};
use crate::culling::{CasterOutcome, Method, Stage};

/// One view's counts from one culled frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewCull {
    pub stages: Vec<Stage>,
    pub casters_rendered: u32,
    pub triangles: u64,
}

/// What came back from one culled frame.
#[derive(Clone, Debug, PartialEq)]
pub struct CullResult {
    pub frame_index: u64,
    pub method: Method,
    pub views: Vec<ViewCull>,
}

/// The stages `method` reports, in order, from one view's counter block.
pub(super) fn view_stages(method: Method, total: u32, words: &[u32]) -> Vec<Stage> {
    let word = |slot: u32| words.get(slot as usize).copied().unwrap_or(0);
    std::iter::once(Stage::new("scene casters", total))
        .chain(
            method
                .stages()
                .iter()
                .map(|kind| Stage::new(kind.name(), word(kind.slot()))),
        )
        .collect()
}

/// Frames in flight and the newest results.
#[derive(Default)]
pub(super) struct CullResults {
    /// Frame index, method, scene casters and views of frames in flight.
    in_flight: VecDeque<(u64, Method, u32, u32)>,
    pub latest: Option<CullResult>,
    /// Per view, each instance's outcome, and their frame.
    pub latest_outcomes: Option<(u64, Vec<Vec<CasterOutcome>>)>,
}

impl CullResults {
    pub fn clear(&mut self) {
        self.latest = None;
        self.latest_outcomes = None;
    }

    pub fn submitted(&mut self, frame_index: u64, method: Method, casters_total: u32, views: u32) {
        self.in_flight
            .push_back((frame_index, method, casters_total, views));
        while self.in_flight.len() > 8 {
            self.in_flight.pop_front();
        }
    }

    fn find(&self, frame_index: u64) -> Option<(Method, u32, u32)> {
        self.in_flight
            .iter()
            .find(|(f, ..)| *f == frame_index)
            .map(|&(_, m, t, v)| (m, t, v))
    }

    /// Takes counter words of frame `frame_index` (a block of [`COUNTER_SLOTS`] per view).
    pub fn counters_arrived(&mut self, frame_index: u64, words: &[u32]) {
        let Some((method, total, views)) = self.find(frame_index) else {
            return;
        };
        let views = words
            .chunks(COUNTER_SLOTS as usize)
            .take(views as usize)
            .map(|block| ViewCull {
                stages: view_stages(method, total, block),
                casters_rendered: block[SLOT_RENDERED as usize],
                triangles: u64::from(block[SLOT_TRIANGLES as usize]),
            })
            .collect();
        self.latest = Some(CullResult {
            frame_index,
            method,
            views,
        });
    }

    /// Takes state words of frame `frame_index` (a block of `instances` per view).
    pub fn states_arrived(&mut self, frame_index: u64, words: &[u32], instances: u32) {
        let Some((method, _, views)) = self.find(frame_index) else {
            return;
        };
        let outcomes = (0..views as usize)
            .map(|v| {
                let block = v * instances as usize;
                words
                    .get(block..block + instances as usize)
                    .unwrap_or_default()
                    .iter()
                    .map(|&w| outcome_from_code(w, method))
                    .collect()
            })
            .collect();
        self.latest_outcomes = Some((frame_index, outcomes));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::culling::StageKind;

    #[test]
    fn every_gpu_method_reports_its_stages() {
        let mut words = vec![0; COUNTER_SLOTS as usize];
        let remaining = [90, 50, 20, 19, 15, 12, 8, 20];
        for (kind, remaining) in StageKind::ALL.iter().zip(remaining) {
            words[kind.slot() as usize] = remaining;
        }
        let frag = view_stages(Method::Frag, 100, &words);
        let names: Vec<_> = frag.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "scene casters",
                "light frustum",
                "light occlusion",
                "receiver mask",
                "footprint (texel-exact)"
            ]
        );
        assert_eq!(frag[3].remaining, 20);
        assert_eq!(frag.last().map(|s| s.remaining), Some(8));
        assert_eq!(view_stages(Method::Ref, 100, &words).len(), 4);
        assert_eq!(view_stages(Method::Oracle, 100, &words)[1].remaining, 20);
        let dr = view_stages(Method::DrProgressive, 100, &words);
        assert_eq!(dr.len(), 6);
        assert_eq!(dr[4].remaining, 12);
        assert_eq!(dr[5].remaining, 8);
        assert_eq!(
            view_stages(Method::Incr, 100, &words)[3].name,
            "changed region"
        );
        assert_eq!(
            view_stages(Method::Vfc, 100, &words).len(),
            2,
            "the CPU's frustum test has no footprint stage"
        );
    }

    #[test]
    fn two_views_come_back_apart() {
        let mut results = CullResults::default();
        results.submitted(7, Method::Ref, 10, 2);
        let mut words = vec![0; 2 * COUNTER_SLOTS as usize];
        words[SLOT_RENDERED as usize] = 3;
        words[COUNTER_SLOTS as usize + SLOT_RENDERED as usize] = 5;
        results.counters_arrived(7, &words);
        let latest = results.latest.clone().expect("frame 7 was in flight");
        assert_eq!(latest.views.len(), 2);
        assert_eq!(
            latest
                .views
                .iter()
                .map(|v| v.casters_rendered)
                .collect::<Vec<_>>(),
            [3, 5]
        );
        results.counters_arrived(8, &words);
        assert_eq!(
            results.latest.map(|r| r.frame_index),
            Some(7),
            "a frame that is not in flight is ignored"
        );
    }
}
