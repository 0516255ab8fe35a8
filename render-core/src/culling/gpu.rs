//! Caster culling on the GPU (Bittner 2011, DigitalRune): receiver masks in the light's view,
//! max pyramids of the shadow map's depth, of the mask and of the camera's depth, and the
//! two-phase caster tests of `cull.wgsl`.
//! Every instance has one indirect draw whose instance count the tests set to 0 or 1.
//! Nothing waits on the GPU: stage counts and per-object outcomes come back a frame or two
//! later, like the other counters.
//!
//! One frame, after the camera prepass and the visible flags:
//!
//! ```text
//! receiver mask     GEOM/BVOL raster at the mask's size, or FRAG's taps from the camera's
//!                   fragments; then the mask's max pyramid (or the oracle's casters);
//!                   the camera depth's pyramid for DigitalRune's shadow volumes
//! first phase       visible receivers (GEOM, FRAG) and last frame's light-visible casters
//! shadow map        those casters
//! occlusion         the shadow map's max pyramid
//! second phase      every caster: light frustum, occlusion, then the mask or the shadow
//!                   volume against the camera's frustum and depth; survivors drawn next
//! shadow map        the survivors, on top
//! ```

use bytemuck::{Pod, Zeroable};

use crate::frame::scene_gpu::{SceneGpu, VERTEX_LAYOUT};
use crate::frame::{CasterOutcome, Method, Stage};
use crate::gpu::{AsyncReadback, GpuContext, GpuCounters, buffer_entry, view_entry};

const CULL_COMMON_WGSL: &str = include_str!("cull_common.wgsl");
const CULL_WGSL: &str = include_str!("cull.wgsl");
const MASKS_WGSL: &str = include_str!("masks.wgsl");
const RECEIVERS_WGSL: &str = include_str!("receivers.wgsl");
const PYRAMID_WGSL: &str = include_str!("pyramid.wgsl");

/// The mask is at most this many texels wide; larger shadow maps share mask texels.
pub const MAX_MASK_SIZE: u32 = 2048;
const MASK_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
const WORKGROUP: u32 = 64;

/// Method bits of `CullParams::params.x` (keep in sync with `culling/cull_common.wgsl`).
mod bits {
    pub const OCCLUSION: u32 = 1;
    pub const MASK: u32 = 2;
    pub const DRAW_RECEIVERS: u32 = 4;
    pub const ORACLE: u32 = 8;
    pub const TEMPORAL: u32 = 16;
    pub const GEOM: u32 = 32;
    pub const BVOL: u32 = 64;
    pub const FRAG: u32 = 128;
    pub const VOLUME: u32 = 256;
    pub const PROGRESSIVE: u32 = 512;
    pub const INCREMENTAL: u32 = 1024;
}

/// Which parts of the pipeline a method uses; `None` for the CPU methods.
fn method_bits(method: Method) -> Option<u32> {
    use bits::{
        BVOL, DRAW_RECEIVERS, FRAG, GEOM, INCREMENTAL, MASK, OCCLUSION, ORACLE, PROGRESSIVE,
        TEMPORAL, VOLUME,
    };
    let occlusion = OCCLUSION | TEMPORAL;
    Some(match method {
        Method::None | Method::Vfc => return None,
        // FOCUS culls like REF; its light frustum is fitted to the visible receivers.
        Method::Ref | Method::Focus => occlusion,
        Method::DrConservative => occlusion | VOLUME,
        Method::DrProgressive => occlusion | VOLUME | PROGRESSIVE,
        Method::Bvol => occlusion | MASK | BVOL,
        Method::Geom => occlusion | MASK | GEOM | DRAW_RECEIVERS,
        Method::GeomBvol => occlusion | MASK | GEOM | BVOL | DRAW_RECEIVERS,
        Method::Frag => occlusion | MASK | FRAG | DRAW_RECEIVERS,
        Method::Incr => MASK | INCREMENTAL,
        Method::Oracle => ORACLE,
    })
}

/// Counter slots (keep in sync with `Counters` in culling/cull.wgsl).
#[derive(Clone, Copy)]
enum Counter {
    InFrustum = 0,
    NotOccluded = 1,
    InMask = 2,
    Rendered = 3,
    Triangles = 4,
    InCameraFrustum = 6,
    NotCameraOccluded = 7,
}
const COUNTERS: usize = 8;

/// Mirrors `CullParams` in `culling/cull_common.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct CullParams {
    light_clip_from_world: [[f32; 4]; 4],
    world_from_light_clip: [[f32; 4]; 4],
    camera_clip_from_world: [[f32; 4]; 4],
    sizes: [u32; 4],
    params: [u32; 4],
    camera: [u32; 4],
    volume: [f32; 4],
}

/// What came back from one culled frame.
#[derive(Clone, Debug, PartialEq)]
pub struct CullResult {
    pub frame_index: u64,
    pub method: Method,
    pub stages: Vec<Stage>,
    pub casters_rendered: u32,
    pub triangles: u64,
}

/// One frame's inputs to [`GpuCulling::encode`].
pub struct CullFrame<'a> {
    pub method: Method,
    pub frame_index: u64,
    pub light_clip_from_world: glam::Mat4,
    pub camera_clip_from_world: glam::Mat4,
    /// How far a shadow volume starts before its caster, in normalised light depth.
    pub volume_depth_pad: f32,
    pub casters_total: u32,
    /// For incremental updates: the map holds nothing usable (first frame, new light, scene
    /// or exclusions): clear it and draw every caster.
    pub full_redraw: bool,
    /// Texels a whole-receiver mask is widened by: the PCF radius, the normal offset, and a
    /// texel for rasterisation.
    pub mask_pad_texels: u32,
    pub visible_flags: &'a wgpu::Buffer,
    pub frame_bind_group: &'a wgpu::BindGroup,
    /// The camera's depth (for the EQUAL-tested receiver passes).
    pub camera_depth: &'a wgpu::TextureView,
}

/// A max pyramid in one buffer (culling/pyramid.wgsl): level m is max((base / 2) >> m, 1)
/// texels square and holds blocks of 2^(m+1) base texels.
struct Pyramid {
    buffer: wgpu::Buffer,
    widths: Vec<u32>,
    /// Per level, for the reduce pass: level 0 reads the base, later levels the one before.
    groups: Vec<wgpu::BindGroup>,
}

impl Pyramid {
    /// `first` reduces the base, read through `base_entries`; `reduce` every later level.
    fn new(
        device: &wgpu::Device,
        label: &str,
        base: u32,
        (first, reduce): (&wgpu::ComputePipeline, &wgpu::ComputePipeline),
        base_entries: &[wgpu::BindGroupEntry<'_>],
    ) -> Self {
        use wgpu::util::DeviceExt;
        let (mut levels, mut widths) = (Vec::new(), Vec::new());
        let (mut width, mut offset, mut source) = ((base / 2).max(1), 0u32, (0u32, base));
        loop {
            let words = [offset, width, source.0, source.1];
            levels.push(
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytemuck::cast_slice(&words),
                    usage: wgpu::BufferUsages::UNIFORM,
                }),
            );
            widths.push(width);
            source = (offset, width);
            offset += width * width;
            if width == 1 {
                break;
            }
            width = (width / 2).max(1);
        }
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: u64::from(offset) * 4,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let groups = levels
            .iter()
            .enumerate()
            .map(|(m, level)| {
                let pipeline = if m == 0 { first } else { reduce };
                let mut entries = vec![buffer_entry(0, &buffer), buffer_entry(1, level)];
                if m == 0 {
                    entries.extend_from_slice(base_entries);
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
            groups,
        }
    }
}

/// Per shadow-map resolution: pyramids and the mask.
struct SizedResources {
    resolution: u32,
    /// The shadow map's depth, where incremental updates clear the changed region.
    shadow_depth: wgpu::TextureView,
    mask_size: u32,
    occlusion: Pyramid,
    mask: Pyramid,
    mask_raster_view: wgpu::TextureView,
    mask_bits: wgpu::Buffer,
}

impl SizedResources {
    /// `shadow_depth` is the shadow map's depth at `resolution`, the occlusion pyramid's base.
    fn new(
        device: &wgpu::Device,
        resolution: u32,
        shadow_depth: &wgpu::TextureView,
        reduce: &ReducePipelines,
    ) -> Self {
        let mask_size = mask_size(resolution);
        let mask_raster = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("GpuCulling::mask_raster"),
            size: wgpu::Extent3d {
                width: mask_size,
                height: mask_size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: MASK_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let mask_raster_view = mask_raster.create_view(&wgpu::TextureViewDescriptor::default());
        let mask_bits = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("GpuCulling::mask_bits"),
            size: u64::from(mask_size) * u64::from(mask_size) * 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let occlusion = Pyramid::new(
            device,
            "GpuCulling::occlusion_pyramid",
            resolution,
            (&reduce.depth, &reduce.level),
            &[view_entry(2, shadow_depth)],
        );
        let mask = Pyramid::new(
            device,
            "GpuCulling::mask_pyramid",
            mask_size,
            (&reduce.mask, &reduce.level),
            &[
                view_entry(3, &mask_raster_view),
                buffer_entry(4, &mask_bits),
            ],
        );
        Self {
            resolution,
            shadow_depth: shadow_depth.clone(),
            mask_size,
            occlusion,
            mask,
            mask_raster_view,
            mask_bits,
        }
    }
}

/// The reduce passes of culling/pyramid.wgsl: from the shadow map's depth, from the mask,
/// from the camera's depth, and from the level before.
struct ReducePipelines {
    depth: wgpu::ComputePipeline,
    mask: wgpu::ComputePipeline,
    camera_depth: wgpu::ComputePipeline,
    level: wgpu::ComputePipeline,
}

/// The camera depth's pyramid for DigitalRune's shadow-volume tests, per view size.
struct CameraPyramid {
    size: (u32, u32),
    base: u32,
    pyramid: Pyramid,
}

/// The mask's size for a shadow map: the map's own, or a whole fraction of it.
fn mask_size(resolution: u32) -> u32 {
    let mut size = resolution.max(1);
    while size > MAX_MASK_SIZE && size.is_multiple_of(2) {
        size /= 2;
    }
    size
}

/// Per scene: one indirect draw per instance, states, the oracle and exclusion flags.
struct SceneResources {
    scene_id: u64,
    instance_count: u32,
    draws: wgpu::Buffer,
    receiver_draws: wgpu::Buffer,
    state: wgpu::Buffer,
    selection: wgpu::Buffer,
    /// Copied into `selection` every frame: the exclusion bits, oracle bits clear.
    selection_init: wgpu::Buffer,
    /// Last frame's boxes (incremental updates).
    previous_bounds: wgpu::Buffer,
    state_readback: AsyncReadback,
}

impl SceneResources {
    fn new(ctx: &GpuContext, scene_gpu: &SceneGpu, excluded: &[u32]) -> Self {
        use wgpu::util::DeviceExt;
        let device = &ctx.device;
        let args: Vec<u8> = scene_gpu
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
            .chain(std::iter::repeat_n(0, 20))
            .collect();
        let draws_buffer = |label| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: &args,
                usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::STORAGE,
            })
        };
        let count = scene_gpu.instance_count.max(1);
        let words = u64::from(count) * 4;
        let storage = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: words,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | usage,
                mapped_at_creation: false,
            })
        };
        let resources = Self {
            scene_id: scene_gpu.id,
            instance_count: scene_gpu.instance_count,
            draws: draws_buffer("GpuCulling::draws"),
            receiver_draws: draws_buffer("GpuCulling::receiver_draws"),
            state: storage("GpuCulling::state", wgpu::BufferUsages::COPY_SRC),
            selection: storage("GpuCulling::selection", wgpu::BufferUsages::empty()),
            selection_init: storage("GpuCulling::selection_init", wgpu::BufferUsages::COPY_SRC),
            previous_bounds: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("GpuCulling::previous_bounds"),
                size: scene_gpu.bounds_buffer.size(),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            state_readback: AsyncReadback::new(device, "GpuCulling::state_readback", words, 3),
        };
        resources.write_exclusions(ctx, excluded);
        resources
    }

    fn write_exclusions(&self, ctx: &GpuContext, excluded: &[u32]) {
        let mut words = vec![0u32; self.instance_count.max(1) as usize];
        for &i in excluded {
            if let Some(w) = words.get_mut(i as usize) {
                *w = 2;
            }
        }
        ctx.queue
            .write_buffer(&self.selection_init, 0, bytemuck::cast_slice(&words));
    }
}

/// Long-lived pipelines; resources follow the scene and the shadow map's resolution.
pub struct GpuCulling {
    params: wgpu::Buffer,
    mask_params: wgpu::Buffer,
    cull_layout: wgpu::BindGroupLayout,
    receivers_pipeline: wgpu::ComputePipeline,
    first_pipeline: wgpu::ComputePipeline,
    second_pipeline: wgpu::ComputePipeline,
    far_ends_pipeline: wgpu::ComputePipeline,
    reduce: ReducePipelines,
    mask_layout: wgpu::BindGroupLayout,
    box_pipeline: wgpu::RenderPipeline,
    moved_box_pipeline: wgpu::RenderPipeline,
    clear_moved_pipeline: wgpu::RenderPipeline,
    geometry_pipelines: Vec<wgpu::RenderPipeline>,
    receivers_layout: wgpu::BindGroupLayout,
    fragment_mask_pipeline: Option<wgpu::RenderPipeline>,
    oracle_pipeline: Option<wgpu::RenderPipeline>,
    counters: GpuCounters<COUNTERS>,
    sized: Option<SizedResources>,
    camera: Option<CameraPyramid>,
    scene: Option<SceneResources>,
    /// This frame's caster-test bind group, from the first phase to the second.
    cull_group: Option<wgpu::BindGroup>,
    excluded: Vec<u32>,
    exclusions_changed: bool,
    /// Methods of frames in flight, by frame index, to label what comes back.
    in_flight: std::collections::VecDeque<(u64, Method, u32)>,
    latest: Option<CullResult>,
    latest_outcomes: Option<(u64, Vec<CasterOutcome>)>,
}

impl GpuCulling {
    /// `frame_layout` and `scene_prelude` are the scene passes' group 0 and its WGSL;
    /// `camera_prelude` adds the camera's vertex stage and shadow lookup.
    pub fn new(
        ctx: &GpuContext,
        frame_layout: &wgpu::BindGroupLayout,
        scene_prelude: &str,
        camera_prelude: &str,
    ) -> Self {
        let device = &ctx.device;
        let uniform = |label, size: usize| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let module = |label, source: String| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            })
        };
        let cull_module = module(
            "GpuCulling::cull",
            format!("{CULL_COMMON_WGSL}\n{CULL_WGSL}"),
        );
        let cull_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("GpuCulling::cull_layout"),
            entries: &[
                layout_entry(0, wgpu::ShaderStages::COMPUTE, uniform_binding()),
                layout_entry(1, wgpu::ShaderStages::COMPUTE, storage_binding(true)),
                layout_entry(2, wgpu::ShaderStages::COMPUTE, storage_binding(true)),
                layout_entry(3, wgpu::ShaderStages::COMPUTE, storage_binding(false)),
                layout_entry(4, wgpu::ShaderStages::COMPUTE, storage_binding(false)),
                layout_entry(5, wgpu::ShaderStages::COMPUTE, storage_binding(false)),
                layout_entry(6, wgpu::ShaderStages::COMPUTE, storage_binding(true)),
                layout_entry(7, wgpu::ShaderStages::COMPUTE, storage_binding(true)),
                layout_entry(8, wgpu::ShaderStages::COMPUTE, storage_binding(true)),
                layout_entry(9, wgpu::ShaderStages::COMPUTE, storage_binding(false)),
                layout_entry(10, wgpu::ShaderStages::COMPUTE, storage_binding(true)),
            ],
        });
        let cull_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("GpuCulling::cull_pipeline_layout"),
            bind_group_layouts: &[Some(&cull_layout)],
            immediate_size: 0,
        });
        let compute =
            |module: &wgpu::ShaderModule, layout: Option<&wgpu::PipelineLayout>, entry| {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout,
                    module,
                    entry_point: Some(entry),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    cache: None,
                })
            };
        let pyramid_module = module("GpuCulling::pyramid", PYRAMID_WGSL.to_owned());

        let mask_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("GpuCulling::mask_layout"),
            entries: &[
                layout_entry(0, wgpu::ShaderStages::VERTEX, uniform_binding()),
                layout_entry(1, wgpu::ShaderStages::VERTEX, storage_binding(true)),
                layout_entry(2, wgpu::ShaderStages::VERTEX, storage_binding(true)),
                layout_entry(3, wgpu::ShaderStages::VERTEX, storage_binding(true)),
                layout_entry(4, wgpu::ShaderStages::VERTEX, storage_binding(true)),
            ],
        });
        let masks_module = module(
            "GpuCulling::masks",
            format!("{scene_prelude}\n{CULL_COMMON_WGSL}\n{MASKS_WGSL}"),
        );
        let masks_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("GpuCulling::masks_layout"),
            bind_group_layouts: &[Some(frame_layout), Some(&mask_layout)],
            immediate_size: 0,
        });
        let mask_pipeline = |entry, with_vertices: bool, polygon_mode, conservative| {
            let vertex_buffers = [Some(VERTEX_LAYOUT)];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(entry),
                layout: Some(&masks_layout),
                vertex: wgpu::VertexState {
                    module: &masks_module,
                    entry_point: Some(entry),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers: if with_vertices { &vertex_buffers } else { &[] },
                },
                primitive: wgpu::PrimitiveState {
                    polygon_mode,
                    conservative,
                    ..Default::default()
                },
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &masks_module,
                    entry_point: Some("fs_mark"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: &[Some(MASK_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        // GEOM must mark every texel a receiver touches, however thin: conservative
        // rasterisation where the device has it, else its triangles filled and outlined.
        let features = ctx.features();
        let geometry_pipelines = if features.contains(wgpu::Features::CONSERVATIVE_RASTERIZATION) {
            vec![mask_pipeline(
                "vs_geometry",
                true,
                wgpu::PolygonMode::Fill,
                true,
            )]
        } else if features.contains(wgpu::Features::POLYGON_MODE_LINE) {
            vec![
                mask_pipeline("vs_geometry", true, wgpu::PolygonMode::Fill, false),
                mask_pipeline("vs_geometry", true, wgpu::PolygonMode::Line, false),
            ]
        } else {
            Vec::new()
        };
        if geometry_pipelines.is_empty() {
            log::warn!(
                "no conservative rasterisation or line polygons: GEOM masks use bounding boxes"
            );
        }

        // Incremental updates clear the changed region of the shadow map to the far plane.
        let clear_moved_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("GpuCulling::clear_moved"),
            layout: Some(&masks_layout),
            vertex: wgpu::VertexState {
                module: &masks_module,
                entry_point: Some("vs_clear_moved"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: crate::shadow_map::SHADOW_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &masks_module,
                entry_point: Some("fs_clear"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        });

        let receivers_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("GpuCulling::receivers_layout"),
            entries: &[
                layout_entry(0, wgpu::ShaderStages::FRAGMENT, uniform_binding()),
                layout_entry(1, wgpu::ShaderStages::FRAGMENT, storage_binding(false)),
                layout_entry(
                    2,
                    wgpu::ShaderStages::FRAGMENT,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                layout_entry(
                    3,
                    wgpu::ShaderStages::FRAGMENT,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Uint,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                layout_entry(4, wgpu::ShaderStages::FRAGMENT, storage_binding(false)),
            ],
        });
        // The receiver passes need forced early depth tests: without them FRAG has no mask
        // (it marks everything) and the oracle method draws every caster.
        let early_depth = features.contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST);
        let (fragment_mask_pipeline, oracle_pipeline) = if early_depth {
            let receivers_module = module(
                "GpuCulling::receivers",
                format!("{camera_prelude}\n{RECEIVERS_WGSL}"),
            );
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("GpuCulling::receivers_pipeline_layout"),
                bind_group_layouts: &[Some(frame_layout), Some(&receivers_layout)],
                immediate_size: 0,
            });
            // Depth EQUAL, no writes, no colour: exactly the camera's visible fragments.
            let pipeline = |entry| {
                crate::frame::camera_pipeline(
                    device,
                    entry,
                    &layout,
                    &receivers_module,
                    entry,
                    &[],
                    (false, wgpu::CompareFunction::Equal),
                )
            };
            (
                Some(pipeline("fs_fragment_mask")),
                Some(pipeline("fs_oracle")),
            )
        } else {
            log::warn!(
                "no forced early depth tests (SHADER_EARLY_DEPTH_TEST): FRAG runs without its \
                 mask and the oracle method draws every caster in the light frustum"
            );
            (None, None)
        };

        Self {
            params: uniform("GpuCulling::params", size_of::<CullParams>()),
            mask_params: uniform("GpuCulling::mask_params", 16),
            receivers_pipeline: compute(&cull_module, Some(&cull_pipeline_layout), "cs_receivers"),
            first_pipeline: compute(&cull_module, Some(&cull_pipeline_layout), "cs_first_phase"),
            second_pipeline: compute(&cull_module, Some(&cull_pipeline_layout), "cs_second_phase"),
            far_ends_pipeline: compute(&cull_module, Some(&cull_pipeline_layout), "cs_far_ends"),
            cull_layout,
            reduce: ReducePipelines {
                depth: compute(&pyramid_module, None, "cs_reduce_depth"),
                mask: compute(&pyramid_module, None, "cs_reduce_mask"),
                camera_depth: compute(&pyramid_module, None, "cs_reduce_camera_depth"),
                level: compute(&pyramid_module, None, "cs_reduce"),
            },
            mask_layout,
            box_pipeline: mask_pipeline("vs_box", false, wgpu::PolygonMode::Fill, false),
            moved_box_pipeline: mask_pipeline(
                "vs_moved_box",
                false,
                wgpu::PolygonMode::Fill,
                false,
            ),
            clear_moved_pipeline,
            geometry_pipelines,
            receivers_layout,
            fragment_mask_pipeline,
            oracle_pipeline,
            counters: GpuCounters::new(device, "GpuCulling::counters"),
            sized: None,
            camera: None,
            scene: None,
            cull_group: None,
            excluded: Vec::new(),
            exclusions_changed: false,
            in_flight: std::collections::VecDeque::new(),
            latest: None,
            latest_outcomes: None,
        }
    }

    /// Whether `method` culls here (the CPU methods do not).
    pub fn handles(method: Method) -> bool {
        method_bits(method).is_some()
    }

    /// Leaves these instances out from the next frame on.
    pub fn exclude(&mut self, instances: &[u32]) {
        self.excluded = instances.to_vec();
        self.exclusions_changed = true;
    }

    /// Follows the scene and the shadow map (`shadow_depth`, `resolution` texels square).
    pub fn prepare(
        &mut self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
        resolution: u32,
        shadow_depth: &wgpu::TextureView,
    ) {
        if self
            .sized
            .as_ref()
            .is_none_or(|s| s.resolution != resolution)
        {
            self.sized = Some(SizedResources::new(
                &ctx.device,
                resolution,
                shadow_depth,
                &self.reduce,
            ));
        }
        if self
            .scene
            .as_ref()
            .is_none_or(|s| s.scene_id != scene_gpu.id)
        {
            self.scene = Some(SceneResources::new(ctx, scene_gpu, &self.excluded));
            self.latest = None;
            self.latest_outcomes = None;
        } else if self.exclusions_changed
            && let Some(scene) = &self.scene
        {
            scene.write_exclusions(ctx, &self.excluded);
        }
        self.exclusions_changed = false;
    }

    /// Follows the camera's view: `depth` is its depth target, `size` pixels.
    pub fn prepare_camera(
        &mut self,
        ctx: &GpuContext,
        size: (u32, u32),
        depth: &wgpu::TextureView,
    ) {
        if self.camera.as_ref().is_none_or(|c| c.size != size) {
            let base = size.0.max(size.1).max(1);
            self.camera = Some(CameraPyramid {
                size,
                base,
                pyramid: Pyramid::new(
                    &ctx.device,
                    "GpuCulling::camera_pyramid",
                    base,
                    (&self.reduce.camera_depth, &self.reduce.level),
                    &[view_entry(2, depth)],
                ),
            });
        }
    }

    /// The indirect draws (one per instance) that the shadow passes issue.
    pub fn draws(&self) -> Option<(&wgpu::Buffer, u32)> {
        self.scene.as_ref().map(|s| (&s.draws, s.instance_count))
    }

    /// The method's bits on this device: without conservative rasterisation or line polygons
    /// GEOM takes boxes; without the receiver passes (no forced early depth tests) FRAG has no
    /// mask and the oracle method draws every caster in the light frustum.
    fn effective_bits(&self, method: Method) -> Option<u32> {
        let mut bits = method_bits(method)?;
        if bits & bits::GEOM != 0 && self.geometry_pipelines.is_empty() {
            bits = (bits & !bits::GEOM) | bits::BVOL;
        }
        if bits & bits::FRAG != 0 && self.fragment_mask_pipeline.is_none() {
            bits &= !(bits::FRAG | bits::MASK);
        }
        if bits & bits::ORACLE != 0 && self.oracle_pipeline.is_none() {
            bits = 0;
        }
        Some(bits)
    }

    /// This frame's bits: an incremental update that must redraw everything has no mask.
    fn frame_bits(&self, frame: &CullFrame<'_>) -> Option<u32> {
        let bits = self.effective_bits(frame.method)?;
        Some(if bits & bits::INCREMENTAL != 0 && frame.full_redraw {
            bits & !bits::MASK
        } else {
            bits
        })
    }

    fn write_params(&self, ctx: &GpuContext, frame: &CullFrame<'_>, method: u32) {
        let (Some(sized), Some(scene), Some(camera)) = (&self.sized, &self.scene, &self.camera)
        else {
            return;
        };
        let params = CullParams {
            light_clip_from_world: frame.light_clip_from_world.to_cols_array_2d(),
            world_from_light_clip: frame.light_clip_from_world.inverse().to_cols_array_2d(),
            camera_clip_from_world: frame.camera_clip_from_world.to_cols_array_2d(),
            sizes: [
                sized.resolution,
                sized.mask_size,
                sized.resolution / sized.mask_size,
                scene.instance_count,
            ],
            params: [method, frame.mask_pad_texels, 0, 0],
            camera: [camera.size.0, camera.size.1, camera.base, 0],
            volume: [frame.volume_depth_pad, 0.0, 0.0, 0.0],
        };
        ctx.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let mask_params = [sized.mask_size, sized.resolution / sized.mask_size, 0, 0];
        ctx.queue
            .write_buffer(&self.mask_params, 0, bytemuck::cast_slice(&mask_params));
    }

    fn cull_bind_group(
        &self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
        visible: &wgpu::Buffer,
    ) -> Option<wgpu::BindGroup> {
        let (sized, scene) = (self.sized.as_ref()?, self.scene.as_ref()?);
        let camera = self.camera.as_ref()?;
        Some(ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuCulling::cull_bind_group"),
            layout: &self.cull_layout,
            entries: &[
                buffer_entry(0, &self.params),
                buffer_entry(1, &scene_gpu.bounds_buffer),
                buffer_entry(2, visible),
                buffer_entry(3, &scene.draws),
                buffer_entry(4, &scene.state),
                buffer_entry(5, self.counters.buffer()),
                buffer_entry(6, &scene.selection),
                buffer_entry(7, &sized.occlusion.buffer),
                buffer_entry(8, &sized.mask.buffer),
                buffer_entry(9, &scene.receiver_draws),
                buffer_entry(10, &camera.pyramid.buffer),
            ],
        }))
    }

    /// Records the mask and the first phase: after it, the shadow map's first pass draws
    /// [`GpuCulling::draws`]. `reference` is the reference map (depth, ids), drawn already when
    /// the method is `oracle`.
    #[expect(
        clippy::too_many_arguments,
        reason = "one step of the frame, all of its inputs"
    )]
    pub fn encode_first_phase(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        camera_draws: &crate::frame::scene_gpu::DrawList,
        indirect_first_instance: bool,
        reference: (&wgpu::TextureView, &wgpu::TextureView),
        frame: &CullFrame<'_>,
    ) -> Option<()> {
        let method = self.frame_bits(frame)?;
        self.write_params(ctx, frame, method);
        let bind_group = self.cull_bind_group(ctx, scene_gpu, frame.visible_flags)?;
        self.cull_group = Some(bind_group.clone());
        let (sized, scene) = (self.sized.as_ref()?, self.scene.as_ref()?);
        let groups = scene.instance_count.div_ceil(WORKGROUP).max(1);
        encoder.copy_buffer_to_buffer(&scene.selection_init, 0, &scene.selection, 0, None);
        self.counters.clear(encoder);

        if method & bits::MASK != 0 {
            encoder.clear_buffer(&sized.mask_bits, 0, None);
            if method & bits::GEOM != 0 {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("GpuCulling::receivers"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&self.receivers_pipeline);
                pass.set_bind_group(0, &bind_group, &[]);
                pass.dispatch_workgroups(groups, 1, 1);
            }
            let mask_group = self.mask_group(ctx, scene_gpu, frame.visible_flags, scene);
            self.rasterise_mask(encoder, scene_gpu, frame, method, &mask_group);
            if method & bits::INCREMENTAL != 0 {
                self.clear_moved(encoder, frame, &mask_group);
            }
        }
        let receiver_pipeline = if method & bits::FRAG != 0 {
            self.fragment_mask_pipeline.as_ref()
        } else if method & bits::ORACLE != 0 {
            self.oracle_pipeline.as_ref()
        } else {
            None
        };
        if let Some(pipeline) = receiver_pipeline {
            self.receiver_pass(
                ctx,
                encoder,
                scene_gpu,
                camera_draws,
                indirect_first_instance,
                reference,
                frame,
                pipeline,
            );
        }
        if method & bits::MASK != 0 {
            self.reduce_chain(encoder, &sized.mask, &self.reduce.mask);
        }
        if method & bits::VOLUME != 0
            && let Some(camera) = &self.camera
        {
            self.reduce_chain(encoder, &camera.pyramid, &self.reduce.camera_depth);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("GpuCulling::first_phase"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.first_pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(groups, 1, 1);
        Some(())
    }

    /// Records the occlusion pyramid of the shadow map (as the first phase left it) and the
    /// second phase; after it, the shadow map's second pass draws [`GpuCulling::draws`] on top
    /// of the first.
    pub fn encode_second_phase(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
    ) -> Option<()> {
        let method = self.frame_bits(frame)?;
        if method & bits::OCCLUSION != 0 {
            let sized = self.sized.as_ref()?;
            self.reduce_chain(encoder, &sized.occlusion, &self.reduce.depth);
        }
        let bind_group = self.cull_group.clone()?;
        let scene = self.scene.as_mut()?;
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("GpuCulling::second_phase"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.second_pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(scene.instance_count.div_ceil(WORKGROUP).max(1), 1, 1);
        }
        self.counters.copy(encoder, frame.frame_index);
        scene
            .state_readback
            .copy(encoder, &scene.state, frame.frame_index);
        if method & bits::INCREMENTAL != 0 {
            encoder.copy_buffer_to_buffer(
                &scene_gpu.bounds_buffer,
                0,
                &scene.previous_bounds,
                0,
                None,
            );
        }
        self.in_flight
            .push_back((frame.frame_index, frame.method, frame.casters_total));
        while self.in_flight.len() > 8 {
            self.in_flight.pop_front();
        }
        Some(())
    }

    /// After the shadow map's second pass, for DigitalRune's progressive mode: the pyramid of
    /// the finished map and each caster's shadow-volume far end for the next frame.
    pub fn encode_far_ends(&mut self, encoder: &mut wgpu::CommandEncoder, method: Method) {
        let bind_group = self.cull_group.take();
        let progressive = self
            .effective_bits(method)
            .is_some_and(|b| b & bits::PROGRESSIVE != 0);
        let (Some(bind_group), Some(sized), Some(scene), true) =
            (bind_group, &self.sized, &self.scene, progressive)
        else {
            return;
        };
        self.reduce_chain(encoder, &sized.occlusion, &self.reduce.depth);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("GpuCulling::far_ends"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.far_ends_pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(scene.instance_count.div_ceil(WORKGROUP).max(1), 1, 1);
    }

    /// The BVOL boxes and GEOM geometry of visible receivers into the mask target.
    fn rasterise_mask(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        method: u32,
        group: &wgpu::BindGroup,
    ) {
        let (Some(sized), Some(scene)) = (&self.sized, &self.scene) else {
            return;
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("GpuCulling::rasterise_mask"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &sized.mask_raster_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_bind_group(1, group, &[]);
        if method & bits::BVOL != 0 {
            pass.set_pipeline(&self.box_pipeline);
            pass.draw(0..6, 0..scene.instance_count);
        }
        if method & bits::INCREMENTAL != 0 {
            pass.set_pipeline(&self.moved_box_pipeline);
            pass.draw(0..12, 0..scene.instance_count);
        }
        if method & bits::GEOM != 0 {
            pass.set_vertex_buffer(0, scene_gpu.vertex_buffer.slice(..));
            pass.set_index_buffer(scene_gpu.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            for pipeline in &self.geometry_pipelines {
                pass.set_pipeline(pipeline);
                pass.multi_draw_indexed_indirect(&scene.receiver_draws, 0, scene.instance_count);
            }
        }
    }

    fn mask_group(
        &self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
        visible: &wgpu::Buffer,
        scene: &SceneResources,
    ) -> wgpu::BindGroup {
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuCulling::mask_bind_group"),
            layout: &self.mask_layout,
            entries: &[
                buffer_entry(0, &self.params),
                buffer_entry(1, &scene_gpu.bounds_buffer),
                buffer_entry(2, visible),
                buffer_entry(3, &scene.state),
                buffer_entry(4, &scene.previous_bounds),
            ],
        })
    }

    /// Incremental updates: the moving objects' old and new boxes cleared in the shadow map
    /// (to the far plane), before the casters that touch them are drawn again.
    fn clear_moved(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &CullFrame<'_>,
        group: &wgpu::BindGroup,
    ) {
        let (Some(sized), Some(scene)) = (&self.sized, &self.scene) else {
            return;
        };
        let mut pass = depth_pass(encoder, "GpuCulling::clear_moved", &sized.shadow_depth);
        pass.set_pipeline(&self.clear_moved_pipeline);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_bind_group(1, group, &[]);
        pass.draw(0..12, 0..scene.instance_count);
    }

    /// FRAG's taps or the oracle's casters, from the camera's visible fragments.
    #[expect(clippy::too_many_arguments, reason = "one pass, all of its inputs")]
    fn receiver_pass(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        camera_draws: &crate::frame::scene_gpu::DrawList,
        indirect_first_instance: bool,
        (reference_depth, reference_ids): (&wgpu::TextureView, &wgpu::TextureView),
        frame: &CullFrame<'_>,
        pipeline: &wgpu::RenderPipeline,
    ) {
        let (Some(sized), Some(scene)) = (&self.sized, &self.scene) else {
            return;
        };
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuCulling::receivers_bind_group"),
            layout: &self.receivers_layout,
            entries: &[
                buffer_entry(0, &self.mask_params),
                buffer_entry(1, &sized.mask_bits),
                view_entry(2, reference_depth),
                view_entry(3, reference_ids),
                buffer_entry(4, &scene.selection),
            ],
        });
        let mut pass = depth_pass(encoder, "GpuCulling::receiver_pass", frame.camera_depth);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        camera_draws.draw(&mut pass, scene_gpu, indirect_first_instance);
    }

    /// Each level of `pyramid` from its base (with `first`) or the level before, a pass each.
    fn reduce_chain(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pyramid: &Pyramid,
        first: &wgpu::ComputePipeline,
    ) {
        for (m, (group, width)) in pyramid.groups.iter().zip(&pyramid.widths).enumerate() {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("GpuCulling::pyramid"),
                timestamp_writes: None,
            });
            pass.set_pipeline(if m == 0 { first } else { &self.reduce.level });
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(width.div_ceil(8), width.div_ceil(8), 1);
        }
    }

    /// Call after submit.
    pub fn after_submit(&mut self) {
        self.counters.after_submit();
        if let Some(scene) = &mut self.scene {
            scene.state_readback.map_copied();
        }
    }

    /// Takes what has come back (needs a device poll first).
    pub fn collect(&mut self) {
        if let Some((frame_index, words)) = self.counters.take_latest()
            && let Some(&(_, method, total)) =
                self.in_flight.iter().find(|(f, _, _)| *f == frame_index)
        {
            self.latest = Some(CullResult {
                frame_index,
                method,
                stages: stages(method, total, &words),
                casters_rendered: words[Counter::Rendered as usize],
                triangles: u64::from(words[Counter::Triangles as usize]),
            });
        }
        if let Some(scene) = &mut self.scene
            && let Some((frame_index, bytes)) = scene.state_readback.take_latest()
        {
            let words: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
            let outcomes = words
                .iter()
                .take(scene.instance_count as usize)
                .map(|&w| crate::frame::gpu_data::outcome_from_code(w & 0xff))
                .collect();
            self.latest_outcomes = Some((frame_index, outcomes));
        }
    }

    /// The newest counts that have come back.
    pub fn latest(&self) -> Option<&CullResult> {
        self.latest.as_ref()
    }

    /// The newest per-instance outcomes that have come back, and their frame.
    pub fn latest_outcomes(&self) -> Option<(u64, &[CasterOutcome])> {
        self.latest_outcomes
            .as_ref()
            .map(|(f, o)| (*f, o.as_slice()))
    }

    /// What the light's view inset shows of `method`'s mask: the mask raster, FRAG's
    /// per-texel depths, and shadow texels per mask texel; `show` bits for the inset
    /// (`frame/light_inset.rs`).
    pub(crate) fn mask_for_inset(
        &self,
        method: Method,
    ) -> Option<(&wgpu::TextureView, &wgpu::Buffer, u32, u32)> {
        use crate::frame::light_inset::show;
        let sized = self.sized.as_ref()?;
        let bits = self.effective_bits(method).unwrap_or(0);
        let mut shown = 0;
        if bits & (bits::GEOM | bits::BVOL | bits::INCREMENTAL) != 0 {
            shown |= show::RASTER_MASK;
        }
        if bits & bits::FRAG != 0 {
            shown |= show::FRAGMENT_MASK;
        }
        Some((
            &sized.mask_raster_view,
            &sized.mask_bits,
            sized.resolution / sized.mask_size,
            shown,
        ))
    }

    /// Per-instance state words (outcome code in the low byte), bound by the `casters`
    /// overlay.
    pub fn state_buffer(&self) -> Option<&wgpu::Buffer> {
        self.scene.as_ref().map(|s| &s.state)
    }
}

/// The stages a method reports, in order, with what remains after each.
fn stages(method: Method, total: u32, words: &[u32; COUNTERS]) -> Vec<Stage> {
    let stage = |name: &str, remaining| Stage {
        name: name.into(),
        remaining,
    };
    let mut out = vec![stage("scene casters", total)];
    if method == Method::Oracle {
        out.push(stage("oracle", words[Counter::Rendered as usize]));
        return out;
    }
    out.push(stage("light frustum", words[Counter::InFrustum as usize]));
    out.push(stage(
        "light occlusion",
        words[Counter::NotOccluded as usize],
    ));
    let bits = method_bits(method).unwrap_or(0);
    if bits & bits::INCREMENTAL != 0 {
        out.push(stage("changed region", words[Counter::InMask as usize]));
    } else if bits & bits::MASK != 0 {
        out.push(stage("receiver mask", words[Counter::InMask as usize]));
    }
    if bits & bits::VOLUME != 0 {
        out.push(stage(
            "camera frustum (shadow volume)",
            words[Counter::InCameraFrustum as usize],
        ));
        out.push(stage(
            "camera occlusion (shadow volume)",
            words[Counter::NotCameraOccluded as usize],
        ));
    }
    out
}

/// A pass on `depth` alone, keeping what it holds.
fn depth_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    depth: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

fn layout_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty,
        count: None,
    }
}

fn uniform_binding() -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

fn storage_binding(read_only: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
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

    #[test]
    fn every_gpu_method_reports_its_stages() {
        let words = [90, 50, 20, 20, 4000, 7, 15, 12];
        let frag = stages(Method::Frag, 100, &words);
        let names: Vec<_> = frag.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "scene casters",
                "light frustum",
                "light occlusion",
                "receiver mask"
            ]
        );
        assert_eq!(frag.last().map(|s| s.remaining), Some(20));
        assert_eq!(stages(Method::Ref, 100, &words).len(), 3);
        assert_eq!(stages(Method::Oracle, 100, &words)[1].remaining, 20);
        let dr = stages(Method::DrProgressive, 100, &words);
        assert_eq!(dr.len(), 5);
        assert_eq!(dr[4].remaining, 12);
        assert_eq!(stages(Method::Incr, 100, &words)[3].name, "changed region");
        for m in Method::ALL {
            assert_eq!(GpuCulling::handles(m), m.gpu_driven(), "{}", m.name());
        }
    }
}
