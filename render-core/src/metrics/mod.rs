//! Measuring a method against the reference: shadow error (visible pixels whose shadow factor
//! differs from the `none` reference with the same shadow views) and the oracle caster set,
//! per shadow view.
//!
//! The shading pass computes each receiver pixel's light from the method and the reference
//! (the technique's light term), counts the pixels that differ, and marks the reference
//! casters that win the depth test at every shadowed PCF tap: the oracle. This module owns
//! the buffers it writes (`metrics/measure.wgsl`; long-lived, grown with the scene and the
//! views) and reads the counts back without stalling.

mod heat_map;

pub use heat_map::HeatMapOverlay;
#[cfg(test)]
pub(crate) use heat_map::shader_source as heat_map_shader_source;

use serde::Serialize;

use crate::gpu::{
    GpuContext, GpuCounters, GpuError, bind_group_layout, buffer_entry, read_buffer, storage,
};
use crate::scene_gpu::SceneGpu;
pub use crate::technique::Undersampling;

/// Counter words before the per-view oracle counts (`Measured` in measure.wgsl).
const ERROR_WORDS: usize = 3;
/// Bins of a view's undersampling histogram (`UNDERSAMPLING_BINS` in measure.wgsl): exactly
/// 0 octaves, then quarter octaves, the last open above 7.75.
pub const UNDERSAMPLING_BINS: usize = 33;

impl Undersampling {
    /// From a histogram of [`UNDERSAMPLING_BINS`] bins; `None` when it is empty. A
    /// percentile is the middle of its bin (0 for the first).
    pub fn from_histogram(bins: &[u32]) -> Option<Self> {
        let pixels: u64 = bins.iter().map(|&b| u64::from(b)).sum();
        if pixels == 0 {
            return None;
        }
        let percentile = |q: f64| {
            let wanted = (q * pixels as f64).ceil().max(1.0) as u64;
            let mut seen = 0;
            for (b, &count) in bins.iter().enumerate() {
                seen += u64::from(count);
                if seen >= wanted {
                    return if b == 0 { 0.0 } else { (b as f32 - 0.5) / 4.0 };
                }
            }
            (bins.len() as f32 - 1.5) / 4.0
        };
        Some(Self {
            median_octaves: percentile(0.5),
            p95_octaves: percentile(0.95),
            pixels: u32::try_from(pixels).unwrap_or(u32::MAX),
        })
    }
}

/// Shadow error of one frame, in pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct ShadowError {
    /// Visible pixels lit in the method's picture but shadowed (more) in the reference.
    pub missing_shadow_px: u32,
    /// Visible pixels shadowed (more) in the method's picture than in the reference.
    pub extra_shadow_px: u32,
    /// Visible receiver pixels compared.
    pub visible_px: u32,
    /// Against the exact shadow: the differing pixels that are not on an edge of the exact
    /// picture ([`crate::truth::ExactShadow::on_edge`]), the wrong shadow that sampling does not
    /// explain. `None` where the reference is a picture of its own.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub off_edge_px: Option<u32>,
}

/// What came back from one measured frame.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Measured {
    pub frame_index: u64,
    pub error: ShadowError,
    /// Casters in the oracle set, summed over the views.
    pub casters_oracle: u32,
    /// Per view, casters in its oracle set.
    pub oracle_per_view: Vec<u32>,
    /// Per view, its undersampling histogram ([`UNDERSAMPLING_BINS`] bins).
    pub undersampling_per_view: Vec<Vec<u32>>,
}

impl Measured {
    /// Undersampling over every view's pixels.
    pub fn undersampling(&self) -> Option<Undersampling> {
        let mut total = vec![0; UNDERSAMPLING_BINS];
        for histogram in &self.undersampling_per_view {
            for (t, h) in total.iter_mut().zip(histogram) {
                *t += h;
            }
        }
        Undersampling::from_histogram(&total)
    }
}

/// Oracle flags, counters and the shading pass's group 2 (`metrics/measure.wgsl`).
pub struct MeasureResources {
    pub layout: wgpu::BindGroupLayout,
    /// Per view and instance.
    oracle_flags: wgpu::Buffer,
    counters: GpuCounters,
    /// Instances and views the flags hold.
    capacity: (u32, u32),
    /// Views of the frames in flight, by frame index.
    views_in_flight: std::collections::VecDeque<(u64, u32)>,
}

impl MeasureResources {
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = bind_group_layout(
            device,
            "Measure::layout",
            wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            &[storage(false), storage(false), storage(true)],
        );
        Self {
            layout,
            oracle_flags: create_flags(device, 1),
            counters: GpuCounters::new(device, "Measure::counters", ERROR_WORDS + 1),
            capacity: (1, 1),
            views_in_flight: std::collections::VecDeque::new(),
        }
    }

    /// Clears flags and counters for a new frame of `views` views and returns the shading
    /// pass's group 2, which also binds `outcomes` (per view and instance, for the overlay).
    pub fn prepare(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        views: u32,
        outcomes: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let wanted = (scene_gpu.instance_count.max(1), views.max(1));
        if wanted.0 > self.capacity.0 || wanted.1 > self.capacity.1 {
            self.capacity = (
                wanted.0.max(self.capacity.0).next_power_of_two(),
                wanted.1.max(self.capacity.1),
            );
            self.oracle_flags = create_flags(&ctx.device, self.capacity.0 * self.capacity.1);
        }
        self.counters.ensure_words(
            &ctx.device,
            ERROR_WORDS + self.capacity.1 as usize * (1 + UNDERSAMPLING_BINS),
        );
        encoder.clear_buffer(&self.oracle_flags, 0, None);
        self.counters.clear(encoder);
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Measure::bind_group"),
            layout: &self.layout,
            entries: &[
                buffer_entry(0, &self.oracle_flags),
                buffer_entry(1, self.counters.buffer()),
                buffer_entry(2, outcomes),
            ],
        })
    }

    /// Copies this frame's counts for readback; call after the shading pass is recorded.
    pub fn copy_counts(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        frame_index: u64,
        views: u32,
    ) {
        self.counters.copy(encoder, frame_index);
        self.views_in_flight.push_back((frame_index, views));
        while self.views_in_flight.len() > 8 {
            self.views_in_flight.pop_front();
        }
    }

    /// Call after submit.
    pub fn after_submit(&mut self) {
        self.counters.after_submit();
    }

    /// The newest counts that came back (needs a device poll first).
    pub fn take_latest(&mut self) -> Option<Measured> {
        let (frame_index, w) = self.counters.take_latest()?;
        let views = self
            .views_in_flight
            .iter()
            .find(|(f, _)| *f == frame_index)
            .map_or(1, |(_, v)| *v as usize);
        let per_view = w.get(ERROR_WORDS..).unwrap_or_default();
        let oracle_per_view: Vec<u32> = per_view.iter().take(views).copied().collect();
        let undersampling_per_view = (0..views)
            .map(|v| {
                let first = views + v * UNDERSAMPLING_BINS;
                per_view
                    .get(first..first + UNDERSAMPLING_BINS)
                    .map_or_else(|| vec![0; UNDERSAMPLING_BINS], <[u32]>::to_vec)
            })
            .collect();
        Some(Measured {
            frame_index,
            error: ShadowError {
                visible_px: w[0],
                missing_shadow_px: w[1],
                extra_shadow_px: w[2],
                off_edge_px: None,
            },
            casters_oracle: oracle_per_view.iter().sum(),
            oracle_per_view,
            undersampling_per_view,
        })
    }

    /// The oracle flag of every instance from the last submitted frame, over its `views`
    /// views: set where any view's oracle holds the instance. Blocks: for tests and reports,
    /// not the window loop.
    pub fn read_oracle(
        &self,
        ctx: &GpuContext,
        instance_count: u32,
        views: u32,
    ) -> Result<Vec<bool>, GpuError> {
        // The shaders' per-view stride is the instance count (`frame.views.y`).
        let block = instance_count.max(1) as usize;
        let views = views.clamp(1, self.capacity.1);
        let words = u64::from(instance_count.max(1)) * u64::from(views);
        let bytes = read_buffer(ctx, &self.oracle_flags, words * 4, "oracle flags")?;
        let flags: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
        Ok((0..instance_count as usize)
            .map(|i| flags.iter().skip(i).step_by(block).any(|w| *w != 0))
            .collect())
    }
}

fn create_flags(device: &wgpu::Device, count: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("Measure::oracle_flags"),
        size: u64::from(count.max(1)) * 4,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_come_from_the_histogram() {
        let mut bins = vec![0; UNDERSAMPLING_BINS];
        assert_eq!(Undersampling::from_histogram(&bins), None);
        // 60 pixels exact, 30 in [1, 1.25), 10 in [3, 3.25).
        bins[0] = 60;
        bins[5] = 30;
        bins[13] = 10;
        let u = Undersampling::from_histogram(&bins).expect("pixels");
        assert_eq!(u.pixels, 100);
        assert!(u.median_octaves == 0.0, "{u:?}");
        assert!((u.p95_octaves - 3.125).abs() < 1e-6, "{u:?}");
        bins[0] = 0;
        let u = Undersampling::from_histogram(&bins).expect("pixels");
        assert!((u.median_octaves - 1.125).abs() < 1e-6, "{u:?}");
    }
}
