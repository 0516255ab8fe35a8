//! GPU culling's buffers and textures, a block per shadow view: per scene (draws, states,
//! selection), per map size (pyramids of the shadow maps and masks, the mask raster), per
//! camera size (the camera depth's pyramid). Long-lived; rebuilt when what they follow changes.

use wgpu::util::DeviceExt;

use super::gpu_data::LevelGpu;
use crate::culling::codes::SELECTION_EXCLUDED;
use crate::gpu::{AsyncReadback, GpuContext, buffer_entry, view_entry};
use crate::scene_gpu::SceneGpu;
use crate::shadow_view::ViewBuffer;

/// The mask is at most this many texels wide; larger shadow maps share mask texels.
pub const MAX_MASK_SIZE: u32 = 2048;
pub(super) const MASK_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
const DRAW_ARGS_BYTES: u64 = size_of::<wgpu::util::DrawIndexedIndirectArgs>() as u64;
/// One view's draw of its footprint boxes (`FootprintDraw` in culling/cull.wgsl).
pub(super) const FOOTPRINT_DRAW_BYTES: u64 = size_of::<wgpu::util::DrawIndirectArgs>() as u64;

/// The mask's size for a shadow map: the map's own, or a whole fraction of it.
pub(super) fn mask_size(resolution: u32) -> u32 {
    let mut size = resolution.max(1);
    while size > MAX_MASK_SIZE && size.is_multiple_of(2) {
        size /= 2;
    }
    size
}

/// The reduce passes of culling/pyramid.wgsl: from the shadow maps' depth, from the mask,
/// from the camera's depth, and from the level before.
pub(super) struct ReducePipelines {
    pub depth: wgpu::ComputePipeline,
    pub mask: wgpu::ComputePipeline,
    pub camera_depth: wgpu::ComputePipeline,
    pub level: wgpu::ComputePipeline,
}

/// Words per view of a max pyramid over a base `size` texels square (every level from half the
/// base down to one texel).
fn pyramid_words(size: u32) -> u32 {
    let (mut width, mut words) = ((size / 2).max(1), 0u32);
    loop {
        words += width * width;
        if width == 1 {
            return words;
        }
        width = (width / 2).max(1);
    }
}

/// The largest buffer culling binds for `capacity` views of maps `resolution` texels square
/// over `instances` instances: its size in bytes and what it is.
pub(super) fn largest_binding(
    resolution: u32,
    capacity: u32,
    instances: u32,
) -> (u64, &'static str) {
    let views = u64::from(capacity.max(1));
    [
        (
            u64::from(pyramid_words(resolution)) * views * 4,
            "occlusion pyramids",
        ),
        (
            u64::from(mask_size(resolution).pow(2)) * views * 4,
            "receiver masks",
        ),
        (
            u64::from(instances) * views * DRAW_ARGS_BYTES,
            "indirect draws",
        ),
    ]
    .into_iter()
    .max_by_key(|(bytes, _)| *bytes)
    .unwrap_or((0, "nothing"))
}

/// A max pyramid in one buffer (culling/pyramid.wgsl), one block of `words` per view: level m
/// is max((base / 2) >> m, 1) texels square and holds blocks of 2^(m+1) base texels.
pub(super) struct Pyramid {
    pub buffer: wgpu::Buffer,
    pub widths: Vec<u32>,
    /// Words per view.
    pub words: u32,
    /// Per level, for the reduce pass: level 0 reads the base, later levels the one before.
    pub groups: Vec<wgpu::BindGroup>,
}

/// What a pyramid's first level reads.
pub(super) struct PyramidBase<'a> {
    pub size: u32,
    pub views: u32,
    /// Words per view of the base's buffer (the mask bits), else 0.
    pub base_words: u32,
    pub entries: &'a [wgpu::BindGroupEntry<'a>],
}

impl Pyramid {
    /// `first` reduces the base, read through `base.entries`; `reduce` every later level.
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        base: &PyramidBase<'_>,
        (first, reduce): (&wgpu::ComputePipeline, &wgpu::ComputePipeline),
    ) -> Self {
        let (mut levels, mut widths) = (Vec::new(), Vec::new());
        let (mut width, mut offset, mut source) = ((base.size / 2).max(1), 0u32, (0u32, base.size));
        loop {
            levels.push((offset, width, source));
            widths.push(width);
            source = (offset, width);
            offset += width * width;
            if width == 1 {
                break;
            }
            width = (width / 2).max(1);
        }
        let words = offset;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: u64::from(words) * u64::from(base.views.max(1)) * 4,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let groups = levels
            .iter()
            .enumerate()
            .map(|(m, &(offset, width, (src_offset, src_width)))| {
                let params = LevelGpu {
                    level: [offset, width, src_offset, src_width],
                    blocks: [words, base.base_words, 0, 0],
                };
                let level = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytemuck::bytes_of(&params),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                let pipeline = if m == 0 { first } else { reduce };
                let mut entries = vec![buffer_entry(0, &buffer), buffer_entry(1, &level)];
                if m == 0 {
                    entries.extend_from_slice(base.entries);
                }
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(label),
                    layout: &pipeline.get_bind_group_layout(0),
                    entries: &entries,
                })
            })
            .collect();
        Self {
            buffer,
            widths,
            words,
            groups,
        }
    }

    /// Each level from its base (with `first`) or the level before, a pass each, for `views`.
    pub fn reduce(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: (&wgpu::ComputePipeline, &wgpu::ComputePipeline),
        views: u32,
    ) {
        for (m, (group, width)) in self.groups.iter().zip(&self.widths).enumerate() {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("GpuCulling::pyramid"),
                timestamp_writes: None,
            });
            pass.set_pipeline(if m == 0 { pipelines.0 } else { pipelines.1 });
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(width.div_ceil(8), width.div_ceil(8), views.max(1));
        }
    }
}

/// What the per-size resources are built for: map size, view capacity, and the technique's
/// depth array (its generation: a new array needs new pyramid bind groups).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct SizedKey {
    pub resolution: u32,
    pub capacity: u32,
    pub maps_generation: u64,
    pub views_generation: u64,
}

/// Per map size and view capacity: the pyramids and the masks.
pub(super) struct SizedResources {
    pub key: SizedKey,
    pub mask_size: u32,
    pub occlusion: Pyramid,
    pub mask: Pyramid,
    /// One layer per view, and every layer.
    pub mask_layers: Vec<wgpu::TextureView>,
    pub mask_array: wgpu::TextureView,
    /// Per view, a block of mask side squared words (FRAG's depths).
    pub mask_bits: wgpu::Buffer,
    /// GEOM's mask widened by the filter's reach (culling/widen.wgsl), and its first pass.
    pub widened: wgpu::Buffer,
    pub widened_rows: wgpu::Buffer,
}

impl SizedResources {
    /// `shadow_maps` is the technique's depth array (every layer), the occlusion pyramids' base.
    pub fn new(
        device: &wgpu::Device,
        key: SizedKey,
        shadow_maps: &wgpu::TextureView,
        (views, cull_views): (&ViewBuffer, &wgpu::Buffer),
        reduce: &ReducePipelines,
    ) -> Self {
        let mask_size = mask_size(key.resolution);
        let capacity = key.capacity.max(1);
        let mask_raster = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("GpuCulling::mask_raster"),
            size: wgpu::Extent3d {
                width: mask_size,
                height: mask_size,
                depth_or_array_layers: capacity,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: MASK_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let mask_array = mask_raster.create_view(&wgpu::TextureViewDescriptor {
            label: Some("GpuCulling::mask_raster_array"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let mask_layers = (0..capacity)
            .map(|layer| {
                mask_raster.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("GpuCulling::mask_raster_layer"),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: layer,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let mask_words = mask_size * mask_size;
        let mask_buffer = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: u64::from(mask_words) * u64::from(capacity) * 4,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let mask_bits = mask_buffer("GpuCulling::mask_bits");
        let occlusion = Pyramid::new(
            device,
            "GpuCulling::occlusion_pyramid",
            &PyramidBase {
                size: key.resolution,
                views: capacity,
                base_words: 0,
                entries: &[view_entry(5, shadow_maps), buffer_entry(6, views.buffer())],
            },
            (&reduce.depth, &reduce.level),
        );
        let mask = Pyramid::new(
            device,
            "GpuCulling::mask_pyramid",
            &PyramidBase {
                size: mask_size,
                views: capacity,
                base_words: mask_words,
                entries: &[
                    view_entry(3, &mask_array),
                    buffer_entry(4, &mask_bits),
                    buffer_entry(7, cull_views),
                ],
            },
            (&reduce.mask, &reduce.level),
        );
        Self {
            key,
            mask_size,
            occlusion,
            mask,
            mask_layers,
            mask_array,
            mask_bits,
            widened: mask_buffer("GpuCulling::widened_mask"),
            widened_rows: mask_buffer("GpuCulling::widened_mask_rows"),
        }
    }
}

/// The camera depth's pyramid for DigitalRune's shadow-volume tests, per view size.
pub(super) struct CameraPyramid {
    pub size: (u32, u32),
    pub base: u32,
    pub pyramid: Pyramid,
}

impl CameraPyramid {
    pub fn new(
        device: &wgpu::Device,
        size: (u32, u32),
        depth: &wgpu::TextureView,
        reduce: &ReducePipelines,
    ) -> Self {
        let base = size.0.max(size.1).max(1);
        Self {
            size,
            base,
            pyramid: Pyramid::new(
                device,
                "GpuCulling::camera_pyramid",
                &PyramidBase {
                    size: base,
                    views: 1,
                    base_words: 0,
                    entries: &[view_entry(2, depth)],
                },
                (&reduce.camera_depth, &reduce.level),
            ),
        }
    }
}

/// Per scene and view capacity: one indirect draw per instance and view, states, the oracle
/// and exclusion bits, last frame's boxes.
pub(super) struct SceneResources {
    pub scene_id: u64,
    pub instance_count: u32,
    pub capacity: u32,
    pub draws: wgpu::Buffer,
    pub receiver_draws: wgpu::Buffer,
    pub state: wgpu::Buffer,
    pub selection: wgpu::Buffer,
    /// Copied into each view's block of `selection` every frame: the exclusion bits.
    pub selection_init: wgpu::Buffer,
    /// Last frame's boxes (incremental updates).
    pub previous_bounds: wgpu::Buffer,
    pub state_readback: AsyncReadback,
    /// The footprint test: per view the casters the cheap tests kept, and one indirect draw
    /// of their boxes.
    pub candidates: wgpu::Buffer,
    pub footprint_draws: wgpu::Buffer,
    /// With a mask the footprint is the candidates' geometry: one indexed draw per instance
    /// and view, like `draws`.
    pub footprint_geometry: wgpu::Buffer,
    /// Whether a frame has been culled with these states (they hold its light-visible set).
    pub has_history: bool,
}

impl SceneResources {
    pub fn new(ctx: &GpuContext, scene_gpu: &SceneGpu, capacity: u32, excluded: &[u32]) -> Self {
        let device = &ctx.device;
        let capacity = capacity.max(1);
        let view_args: Vec<u8> = scene_gpu
            .instance_ranges
            .iter()
            .enumerate()
            .flat_map(|(i, range)| {
                wgpu::util::DrawIndexedIndirectArgs {
                    index_count: range.index_count,
                    instance_count: 0,
                    first_index: range.first_index,
                    base_vertex: range.base_vertex,
                    first_instance: i as u32,
                }
                .as_bytes()
                .to_vec()
            })
            .collect();
        // One block per view, and a spare draw so that an empty scene has a non-empty buffer.
        let args: Vec<u8> = std::iter::repeat_n(view_args.as_slice(), capacity as usize)
            .flatten()
            .copied()
            .chain(std::iter::repeat_n(0, DRAW_ARGS_BYTES as usize))
            .collect();
        let draws_buffer = |label| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: &args,
                usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::STORAGE,
            })
        };
        let count = scene_gpu.instance_count.max(1);
        let instance_words = u64::from(count) * 4;
        let view_words = instance_words * u64::from(capacity);
        let storage = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | usage,
                mapped_at_creation: false,
            })
        };
        let copy_src = wgpu::BufferUsages::COPY_SRC;
        let resources = Self {
            scene_id: scene_gpu.id,
            instance_count: scene_gpu.instance_count,
            capacity,
            draws: draws_buffer("GpuCulling::draws"),
            receiver_draws: draws_buffer("GpuCulling::receiver_draws"),
            footprint_geometry: draws_buffer("GpuCulling::footprint_geometry"),
            has_history: false,
            state: storage("GpuCulling::state", view_words, copy_src),
            selection: storage("GpuCulling::selection", view_words, copy_src),
            selection_init: storage("GpuCulling::selection_init", instance_words, copy_src),
            previous_bounds: storage(
                "GpuCulling::previous_bounds",
                scene_gpu.bounds_buffer.size(),
                wgpu::BufferUsages::empty(),
            ),
            state_readback: AsyncReadback::new(device, "GpuCulling::state_readback", view_words, 3),
            candidates: storage(
                "GpuCulling::candidates",
                view_words,
                wgpu::BufferUsages::empty(),
            ),
            footprint_draws: storage(
                "GpuCulling::footprint_draws",
                u64::from(capacity) * FOOTPRINT_DRAW_BYTES,
                wgpu::BufferUsages::INDIRECT,
            ),
        };
        resources.write_exclusions(ctx, excluded);
        resources
    }

    pub fn write_exclusions(&self, ctx: &GpuContext, excluded: &[u32]) {
        let mut words = vec![0u32; self.instance_count.max(1) as usize];
        for &i in excluded {
            if let Some(w) = words.get_mut(i as usize) {
                *w = SELECTION_EXCLUDED;
            }
        }
        ctx.queue
            .write_buffer(&self.selection_init, 0, bytemuck::cast_slice(&words));
    }

    /// Byte offset of view `view`'s first draw.
    pub fn draws_offset(&self, view: u32) -> u64 {
        u64::from(view) * u64::from(self.instance_count) * DRAW_ARGS_BYTES
    }

    /// Starts every view's selection from the exclusions.
    pub fn reset_selection(&self, encoder: &mut wgpu::CommandEncoder, views: u32) {
        let block = u64::from(self.instance_count) * 4;
        if block == 0 {
            return;
        }
        for v in 0..u64::from(views) {
            encoder.copy_buffer_to_buffer(
                &self.selection_init,
                0,
                &self.selection,
                v * block,
                block,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_stay_within_limits_and_divide_the_map() {
        assert_eq!(mask_size(2048), 2048);
        assert_eq!(mask_size(4096), 2048);
        assert_eq!(mask_size(8192), 2048);
        assert_eq!(mask_size(3000), 1500);
        assert_eq!(mask_size(1000), 1000);
        for res in [512, 1000, 2048, 3000, 4096, 8192] {
            assert_eq!(res % mask_size(res), 0);
        }
    }
}
