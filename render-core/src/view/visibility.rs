//! Which objects the camera sees, from the object-id target: a flag per object, counts and
//! the visible receivers' bounds, computed on the GPU and read back without stalling.

use super::ViewTargets;
use crate::gpu::{
    FrameTimer, GpuContext, GpuCounters, bind_group_layout, buffer_entry, compute_pipeline,
    pass_label, pipeline_layout, shader_module, storage, texture, view_entry,
};
use crate::scene_gpu::SceneGpu;

/// The visibility pass's shader, as the renderer and the validation test compose it.
pub(crate) fn shader_source() -> String {
    crate::shaders::compose("view/visibility.wgsl", &[])
}

/// Counter words: objects, receivers, the receivers' box as 3 + 3 keys (`Counters` in
/// visibility.wgsl).
const COUNTER_WORDS: usize = 10;

/// Counts of one frame's visible objects.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VisibilityCounts {
    pub frame_index: u64,
    pub objects_visible: u32,
    pub receivers_visible: u32,
    /// The visible receivers' world-space bounds (empty when none is visible).
    pub receiver_bounds: crate::geom::Aabb,
    /// The reversed depths (1 near, 0 far) of the receiver pixels: nearest and furthest.
    pub receiver_depths: Option<[f32; 2]>,
}

impl VisibilityCounts {
    /// The view depths, metres, of the receiver pixels of a camera with these planes
    /// (`Camera::clip_from_view` inverted: depth = far near / (near + d (far - near))).
    pub fn receiver_depths_m(&self, near_m: f32, far_m: f32) -> Option<[f32; 2]> {
        let [d_near, d_far] = self.receiver_depths?;
        let view_depth = |d: f32| far_m * near_m / (near_m + d * (far_m - near_m));
        Some([view_depth(d_near), view_depth(d_far)])
    }
}

/// Long-lived compute pipeline; per-scene flag buffer.
pub struct VisibilityPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    /// One `u32` per instance: non-zero when some pixel shows it.
    pub visible_flags: wgpu::Buffer,
    /// Visible objects, visible receivers, their bounds' keys (keep in sync with `Counters` in
    /// visibility.wgsl).
    counters: GpuCounters,
    capacity: u32,
}

impl VisibilityPass {
    pub fn new(ctx: &GpuContext) -> Self {
        let device = &ctx.device;
        let module = shader_module(device, "Visibility::shader", shader_source());
        let layout = bind_group_layout(
            device,
            "Visibility::layout",
            wgpu::ShaderStages::COMPUTE,
            &[
                texture(
                    wgpu::TextureSampleType::Uint,
                    wgpu::TextureViewDimension::D2,
                ),
                storage(true),
                storage(false),
                storage(false),
                storage(true),
                crate::gpu::depth_texture(),
            ],
        );
        let pipeline_layout = pipeline_layout(device, "Visibility::pipeline_layout", &[&layout]);
        let pipeline = compute_pipeline(device, &module, Some(&pipeline_layout), "cs_mark_visible");
        Self {
            pipeline,
            layout,
            visible_flags: create_flags(device, 1),
            counters: GpuCounters::new(device, "Visibility::counters", COUNTER_WORDS),
            capacity: 1,
        }
    }

    /// Clears the flags and counters and marks every object some pixel of the object-id
    /// target shows; timed as its own pass.
    pub fn mark_visible(
        &mut self,
        ctx: &GpuContext,
        (encoder, timer): (&mut wgpu::CommandEncoder, &FrameTimer),
        targets: &ViewTargets,
        scene_gpu: &SceneGpu,
        frame_index: u64,
    ) {
        let (ids_view, size, instances, instance_count) = (
            &targets.ids_view,
            (targets.width, targets.height),
            &scene_gpu.instance_buffer,
            scene_gpu.instance_count,
        );
        if instance_count > self.capacity {
            self.capacity = instance_count.next_power_of_two();
            self.visible_flags = create_flags(&ctx.device, self.capacity);
        }
        encoder.clear_buffer(&self.visible_flags, 0, None);
        self.counters.clear(encoder);
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Visibility::bind_group"),
            layout: &self.layout,
            entries: &[
                view_entry(0, ids_view),
                buffer_entry(1, instances),
                buffer_entry(2, &self.visible_flags),
                buffer_entry(3, self.counters.buffer()),
                buffer_entry(4, &scene_gpu.bounds_buffer),
                view_entry(5, &targets.depth_view),
            ],
        });
        let query = timer.begin_pass(pass_label::VISIBILITY, encoder);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("Visibility::mark_visible"),
                timestamp_writes: query
                    .as_ref()
                    .and_then(wgpu_profiler::GpuProfilerQuery::compute_pass_timestamp_writes),
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(size.0.div_ceil(8), size.1.div_ceil(8), 1);
        }
        timer.end_pass(encoder, query);
        self.counters.copy(encoder, frame_index);
    }

    /// Call after submit.
    pub fn after_submit(&mut self) {
        self.counters.after_submit();
    }

    /// The newest counts that have come back, if any (needs a device poll first).
    pub fn take_latest(&mut self) -> Option<VisibilityCounts> {
        let (frame_index, words) = self.counters.take_latest()?;
        let min = glam::Vec3::from_array(std::array::from_fn(|k| float_of_key(!words[2 + k])));
        let max = glam::Vec3::from_array(std::array::from_fn(|k| float_of_key(words[5 + k])));
        Some(VisibilityCounts {
            frame_index,
            objects_visible: words[0],
            receivers_visible: words[1],
            receiver_bounds: if words[1] == 0 {
                crate::geom::Aabb::EMPTY
            } else {
                crate::geom::Aabb::new(min, max)
            },
            receiver_depths: (words[8] != 0)
                .then(|| [f32::from_bits(words[8]), f32::from_bits(!words[9])]),
        })
    }
}

/// The float behind an order-preserving key of visibility.wgsl (`order_key`).
fn float_of_key(key: u32) -> f32 {
    f32::from_bits(if key & 0x8000_0000 != 0 {
        key & 0x7fff_ffff
    } else {
        !key
    })
}

fn create_flags(device: &wgpu::Device, count: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("Visibility::visible_flags"),
        size: u64::from(count.max(1)) * 4,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::float_of_key;

    /// The CPU side of visibility.wgsl's `order_key`.
    fn order_key(x: f32) -> u32 {
        let b = x.to_bits();
        if b & 0x8000_0000 != 0 {
            !b
        } else {
            b | 0x8000_0000
        }
    }

    #[test]
    fn order_keys_sort_like_floats_and_invert() {
        let values = [-1e30, -2.5, -0.0, 0.0, 1e-20, 3.0, 7e12];
        for w in values.windows(2) {
            assert!(order_key(w[0]) <= order_key(w[1]), "{} vs {}", w[0], w[1]);
        }
        for v in values {
            assert_eq!(float_of_key(order_key(v)).to_bits(), v.to_bits());
        }
    }
}
