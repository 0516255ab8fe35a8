//! Measuring a method against the reference: shadow error (visible pixels whose shadow factor
//! differs from the `none` reference with the same light frustum) and the oracle caster set.
//!
//! The shading pass computes each receiver pixel's shadow factor from both maps, counts the
//! pixels that differ, and marks the reference casters that win the depth test at every
//! shadowed PCF tap: the oracle. This module owns the buffers it writes (long-lived, resized
//! with the scene) and reads the counts back without stalling.

mod heat_map;

pub use heat_map::HeatMapOverlay;

use serde::Serialize;

use crate::frame::SceneGpu;
use crate::gpu::{GpuContext, GpuCounters, GpuError, read_flags};
use crate::shadow_map::ShadowMapPass;

/// Shadow error of one frame, in pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct ShadowError {
    /// Visible pixels lit in the method's picture but shadowed (more) in the reference.
    pub missing_shadow_px: u32,
    /// Visible pixels shadowed (more) in the method's picture than in the reference.
    pub extra_shadow_px: u32,
    /// Visible receiver pixels compared.
    pub visible_px: u32,
}

/// What came back from one measured frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Measured {
    pub frame_index: u64,
    pub error: ShadowError,
    /// Casters in the oracle set.
    pub casters_oracle: u32,
}

/// Oracle flags, counters and the shading pass's group 1 (both shadow maps and these buffers).
pub struct MeasureResources {
    pub layout: wgpu::BindGroupLayout,
    oracle_flags: wgpu::Buffer,
    /// Keep in sync with `Measured` in frame/camera.wgsl: visible, missing, extra, oracle.
    counters: GpuCounters<4>,
    capacity: u32,
    /// Rebuilt when the shadow resolution or the flag buffer changes.
    bind_group: Option<(u32, wgpu::BindGroup)>,
}

impl MeasureResources {
    pub fn new(device: &wgpu::Device) -> Self {
        let texture = |binding, sample_type| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let storage = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("Measure::layout"),
            entries: &[
                texture(0, wgpu::TextureSampleType::Depth),
                texture(1, wgpu::TextureSampleType::Depth),
                texture(2, wgpu::TextureSampleType::Uint),
                storage(3),
                storage(4),
            ],
        });
        Self {
            layout,
            oracle_flags: create_flags(device, 1),
            counters: GpuCounters::new(device, "Measure::counters"),
            capacity: 1,
            bind_group: None,
        }
    }

    /// Clears flags and counters for a new frame and returns the shading pass's group 1.
    pub fn prepare(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        shadow_map: &ShadowMapPass,
        scene_gpu: &SceneGpu,
    ) -> &wgpu::BindGroup {
        if scene_gpu.instance_count > self.capacity {
            self.capacity = scene_gpu.instance_count.next_power_of_two();
            self.oracle_flags = create_flags(&ctx.device, self.capacity);
            self.bind_group = None;
        }
        if self
            .bind_group
            .as_ref()
            .is_none_or(|(resolution, _)| *resolution != shadow_map.resolution)
        {
            let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("Measure::bind_group"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&shadow_map.depth_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(
                            &shadow_map.reference.depth_view,
                        ),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(
                            &shadow_map.reference.ids_view,
                        ),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: self.oracle_flags.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: self.counters.buffer().as_entire_binding(),
                    },
                ],
            });
            self.bind_group = Some((shadow_map.resolution, group));
        }
        encoder.clear_buffer(&self.oracle_flags, 0, None);
        self.counters.clear(encoder);
        &self.bind_group.as_ref().expect("created above").1
    }

    /// Copies this frame's counts for readback; call after the shading pass is recorded.
    pub fn copy_counts(&mut self, encoder: &mut wgpu::CommandEncoder, frame_index: u64) {
        self.counters.copy(encoder, frame_index);
    }

    /// Call after submit.
    pub fn after_submit(&mut self) {
        self.counters.after_submit();
    }

    /// The newest counts that came back (needs a device poll first).
    pub fn take_latest(&mut self) -> Option<Measured> {
        let (frame_index, w) = self.counters.take_latest()?;
        Some(Measured {
            frame_index,
            error: ShadowError {
                visible_px: w[0],
                missing_shadow_px: w[1],
                extra_shadow_px: w[2],
            },
            casters_oracle: w[3],
        })
    }

    /// The oracle flag of every instance from the last submitted frame. Blocks: for tests and
    /// reports, not the window loop.
    pub fn read_oracle(
        &self,
        ctx: &GpuContext,
        instance_count: u32,
    ) -> Result<Vec<bool>, GpuError> {
        read_flags(ctx, &self.oracle_flags, instance_count, "oracle flags")
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
