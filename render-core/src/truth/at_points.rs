//! The technique's light at the truth's surface points, on the GPU (`truth/at_points.wgsl`):
//! one compute pass with the last frame's groups, read back when the GPU is done ([`PendingLight`],
//! the window's way) or at once ([`LightAtPoints::evaluate`], headless). For measuring only.

use bytemuck::{Pod, Zeroable};

use std::sync::mpsc;
use std::time::Duration;

use crate::gpu::{
    GpuContext, GpuError, bind_group_layout, buffer_entry, compute_pipeline, pipeline_layout,
    shader_module, storage,
};
use crate::technique::compose_with_light_term;

/// Points per workgroup (`POINTS_PER_GROUP` in the shader).
const POINTS_PER_GROUP: u32 = 256;
/// Workgroups along x before a second row of groups is started.
const MAX_GROUPS_X: u32 = 65_535;

/// A point the light is wanted at (`SurfacePoint` in the shader).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SurfacePoint {
    /// World position; `w` is 1.
    pub position: [f32; 4],
    /// Unit geometric normal on the camera's side; `w` is 0.
    pub normal: [f32; 4],
}

/// The shader with a technique's light term.
pub(crate) fn shader_source(light_wgsl: &str) -> String {
    compose_with_light_term("truth/at_points.wgsl", light_wgsl)
}

/// The pipeline, built for one technique's light term and the frame's group layouts.
pub struct LightAtPoints {
    pipeline: wgpu::ComputePipeline,
    points_layout: wgpu::BindGroupLayout,
}

/// The groups of the frame the light is read from: frame uniforms and views, the
/// technique's light group, the measure group.
pub struct FrameGroups<'a> {
    pub frame: &'a wgpu::BindGroup,
    pub light: &'a wgpu::BindGroup,
    pub measure: &'a wgpu::BindGroup,
}

impl LightAtPoints {
    /// `layouts`: group 0 of scene passes, the technique's light group, the measure group.
    pub fn new(
        device: &wgpu::Device,
        light_wgsl: &str,
        layouts: [&wgpu::BindGroupLayout; 3],
    ) -> Self {
        let points_layout = bind_group_layout(
            device,
            "Truth::points_layout",
            wgpu::ShaderStages::COMPUTE,
            &[storage(true), storage(false)],
        );
        let module = shader_module(device, "Truth::light_at_points", shader_source(light_wgsl));
        let layout = pipeline_layout(
            device,
            "Truth::light_at_points_layout",
            &[layouts[0], layouts[1], layouts[2], &points_layout],
        );
        Self {
            pipeline: compute_pipeline(device, &module, Some(&layout), "cs_light_at_points"),
            points_layout,
        }
    }

    /// The fraction of light reaching each point in the frame the groups belong to. Blocks.
    pub fn evaluate(
        &self,
        ctx: &GpuContext,
        groups: &FrameGroups<'_>,
        points: &[SurfacePoint],
    ) -> Result<Vec<f32>, GpuError> {
        let pending = self.submit(ctx, groups, points);
        ctx.wait_idle()?;
        // Another thread's poll on the shared device may have taken the mapping and be about to
        // run its callback: wait for it rather than taking "not yet" for an answer.
        pending.take_within(MAPPING_WAIT).unwrap_or_else(|| {
            Err(GpuError::Readback {
                what: WHAT.to_owned(),
                reason: format!(
                    "the GPU finished but the result was not mapped within {} s",
                    MAPPING_WAIT.as_secs()
                ),
            })
        })
    }

    /// Records and submits the pass and its copy to a readable buffer; the light arrives
    /// once a device poll has run after the GPU finished ([`PendingLight::try_take`]).
    pub fn submit(
        &self,
        ctx: &GpuContext,
        groups: &FrameGroups<'_>,
        points: &[SurfacePoint],
    ) -> PendingLight {
        let device = &ctx.device;
        let count = points.len();
        let size = (count.max(1) * 4) as u64;
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("Truth::light_at_staging"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("Truth::light_at_points"),
        });
        if count > 0 {
            let input = wgpu::util::DeviceExt::create_buffer_init(
                device,
                &wgpu::util::BufferInitDescriptor {
                    label: Some("Truth::points"),
                    contents: bytemuck::cast_slice(points),
                    usage: wgpu::BufferUsages::STORAGE,
                },
            );
            let output = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("Truth::light_at"),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let points_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("Truth::points_group"),
                layout: &self.points_layout,
                entries: &[buffer_entry(0, &input), buffer_entry(1, &output)],
            });
            let groups_needed = (count as u32).div_ceil(POINTS_PER_GROUP);
            let (x, y) = (
                groups_needed.min(MAX_GROUPS_X),
                groups_needed.div_ceil(MAX_GROUPS_X),
            );
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("Truth::light_at_points"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, groups.frame, &[]);
                pass.set_bind_group(1, groups.light, &[]);
                pass.set_bind_group(2, groups.measure, &[]);
                pass.set_bind_group(3, &points_group, &[]);
                pass.dispatch_workgroups(x, y, 1);
            }
            encoder.copy_buffer_to_buffer(&output, 0, &staging, 0, size);
        }
        ctx.queue.submit([encoder.finish()]);
        let (sender, mapped) = mpsc::channel();
        staging
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |result| {
                // A failed send only means nobody waits for the light any more.
                let _ = sender.send(result);
            });
        PendingLight {
            staging,
            mapped,
            count,
        }
    }
}

/// What a readback is called in its errors.
const WHAT: &str = "light at the truth's points";

/// How long a blocking readback waits for its mapping after the GPU went idle.
const MAPPING_WAIT: Duration = Duration::from_secs(30);

/// The light at points on its way back from the GPU.
pub struct PendingLight {
    staging: wgpu::Buffer,
    mapped: mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>,
    count: usize,
}

impl PendingLight {
    /// The light at each point once it has come back (after a device poll), else `None`.
    pub fn try_take(&self) -> Option<Result<Vec<f32>, GpuError>> {
        self.take_within(Duration::ZERO)
    }

    /// The light at each point if it comes back within `wait`, else `None`.
    fn take_within(&self, wait: Duration) -> Option<Result<Vec<f32>, GpuError>> {
        let error = |reason: String| GpuError::Readback {
            what: WHAT.to_owned(),
            reason,
        };
        let received = if wait.is_zero() {
            self.mapped.try_recv().map_err(|e| match e {
                mpsc::TryRecvError::Empty => mpsc::RecvTimeoutError::Timeout,
                mpsc::TryRecvError::Disconnected => mpsc::RecvTimeoutError::Disconnected,
            })
        } else {
            self.mapped.recv_timeout(wait)
        };
        let mapped = match received {
            Ok(result) => result.map_err(|e| error(e.to_string())),
            Err(mpsc::RecvTimeoutError::Timeout) => return None,
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                Err(error("the readback was dropped".to_owned()))
            }
        };
        Some(mapped.and_then(|()| {
            let light: Vec<f32> = {
                let view = self
                    .staging
                    .slice(..)
                    .get_mapped_range()
                    .map_err(|e| error(e.to_string()))?;
                bytemuck::pod_collect_to_vec(&view[..self.count * 4])
            };
            self.staging.unmap();
            Ok(light)
        }))
    }
}
