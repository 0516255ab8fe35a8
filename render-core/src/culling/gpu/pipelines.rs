//! GPU culling's long-lived pipelines and layouts, and the shaders they are built from (the
//! validation test composes the same sources). What a device lacks becomes a fallback that
//! the report names (`GpuCulling::device_notes`).

use super::resources::{MASK_FORMAT, ReducePipelines};
use crate::culling::codes;
use crate::gpu::{
    GpuContext, bind_group_layout, compute_pipeline, layout_entry, pipeline_layout, shader_module,
    storage, texture, uniform,
};
use crate::scene_gpu::VERTEX_LAYOUT;
use crate::shaders::compose;
use crate::shadow_view::SHADOW_FORMAT;
use crate::view::camera_pipeline;

/// Every culling shader: its label and its file.
const SHADERS: [(&str, &str); 6] = [
    ("GpuCulling::cull", "culling/cull.wgsl"),
    ("GpuCulling::pyramid", "culling/pyramid.wgsl"),
    ("GpuCulling::masks", "culling/masks.wgsl"),
    ("GpuCulling::receivers", "culling/receivers.wgsl"),
    ("GpuCulling::footprints", "culling/footprints.wgsl"),
    ("GpuCulling::widen", "culling/widen.wgsl"),
];

/// The culling shaders as the renderer builds them: (label, composed WGSL).
#[cfg(test)]
pub(crate) fn shader_sources() -> Vec<(&'static str, String)> {
    SHADERS
        .into_iter()
        .map(|(label, _)| (label, source(label)))
        .collect()
}

/// The shader called `label`, composed with culling's codes.
fn source(label: &str) -> String {
    let codes = codes::wgsl();
    let generated = [(codes::WGSL_PATH, codes.as_str())];
    SHADERS
        .iter()
        .find(|(l, _)| *l == label)
        .map(|(_, root)| compose(root, &generated))
        .unwrap_or_default()
}

/// Every pipeline of GPU culling.
pub(super) struct CullPipelines {
    pub cull_layout: wgpu::BindGroupLayout,
    pub receivers: wgpu::ComputePipeline,
    pub first_phase: wgpu::ComputePipeline,
    pub second_phase: wgpu::ComputePipeline,
    pub far_ends: wgpu::ComputePipeline,
    pub reduce: ReducePipelines,
    pub mask_layout: wgpu::BindGroupLayout,
    pub boxes: wgpu::RenderPipeline,
    pub moved_boxes: wgpu::RenderPipeline,
    pub clear_moved: wgpu::RenderPipeline,
    /// Incremental updates at full mask resolution: moved boxes' faces depth tested into the
    /// mask, then the marked texels cleared.
    pub moved_faces: wgpu::RenderPipeline,
    pub clear_marked: wgpu::RenderPipeline,
    /// Receiver geometry into the mask: one conservative pipeline, or filled then outlined
    /// triangles; none without either (GEOM then takes boxes).
    pub geometry: Vec<wgpu::RenderPipeline>,
    pub receivers_layout: wgpu::BindGroupLayout,
    /// The receiver passes; `None` without forced early depth tests.
    pub fragment_mask: Option<wgpu::RenderPipeline>,
    /// FRAG's mask from the prepass's surface targets, one thread per pixel.
    pub surface_mask_layout: wgpu::BindGroupLayout,
    pub surface_mask: wgpu::ComputePipeline,
    pub oracle: Option<wgpu::RenderPipeline>,
    /// The footprint test: boxes against the mask (first phase) and also the map's depth
    /// (second phase), then the verdict; GEOM's mask widened first.
    pub footprint_layout: wgpu::BindGroupLayout,
    pub footprint_first: wgpu::RenderPipeline,
    pub footprint_second: wgpu::RenderPipeline,
    /// The same with the candidates' geometry (methods with a mask).
    pub footprint_geometry_first: wgpu::RenderPipeline,
    pub footprint_geometry_second: wgpu::RenderPipeline,
    pub resolve: wgpu::ComputePipeline,
    /// After the maps (with `footprint_second`): the drawn casters collected, and which of
    /// them the finished maps show where the mask needs them.
    pub collect_drawn: wgpu::ComputePipeline,
    pub resolve_light_visible: wgpu::ComputePipeline,
    pub widen_layout: wgpu::BindGroupLayout,
    pub widen_rows: wgpu::ComputePipeline,
    pub widen_columns: wgpu::ComputePipeline,
}

/// The groups every scene pass and every single-view pass start with.
pub(super) struct SharedLayouts<'a> {
    /// Group 0 of scene passes (`view/common.wgsl`).
    pub frame: &'a wgpu::BindGroupLayout,
    /// One shadow view (`shadow_view::ViewBuffer::pass_layout`).
    pub pass_view: &'a wgpu::BindGroupLayout,
}

impl CullPipelines {
    pub fn new(ctx: &GpuContext, layouts: &SharedLayouts<'_>) -> Self {
        let device = &ctx.device;
        let compute = wgpu::ShaderStages::COMPUTE;
        let cull_module = shader_module(device, "GpuCulling::cull", source("GpuCulling::cull"));
        let mut cull_types = vec![uniform()];
        cull_types.extend(
            [
                true, true, true, true, false, false, false, true, true, true,
            ]
            .map(storage),
        );
        cull_types.extend([false, true, false, false, false].map(storage));
        let cull_layout =
            bind_group_layout(device, "GpuCulling::cull_layout", compute, &cull_types);
        let cull_pipeline_layout =
            pipeline_layout(device, "GpuCulling::cull_pipeline_layout", &[&cull_layout]);
        let cull =
            |entry| compute_pipeline(device, &cull_module, Some(&cull_pipeline_layout), entry);
        let pyramid = shader_module(device, "GpuCulling::pyramid", source("GpuCulling::pyramid"));
        let reduce = |entry| compute_pipeline(device, &pyramid, None, entry);

        let mask_layout = bind_group_layout(
            device,
            "GpuCulling::mask_layout",
            wgpu::ShaderStages::VERTEX,
            &[
                uniform(),
                storage(true),
                storage(true),
                storage(true),
                storage(true),
                storage(true),
            ],
        );
        let masks = MaskPipelines::new(ctx, layouts, &mask_layout);
        let receivers_layout = bind_group_layout(
            device,
            "GpuCulling::receivers_layout",
            wgpu::ShaderStages::FRAGMENT,
            &[
                storage(true),
                storage(false),
                texture(
                    wgpu::TextureSampleType::Depth,
                    wgpu::TextureViewDimension::D2Array,
                ),
                texture(
                    wgpu::TextureSampleType::Uint,
                    wgpu::TextureViewDimension::D2Array,
                ),
                storage(false),
            ],
        );
        let (fragment_mask, oracle) = receiver_pipelines(ctx, layouts.frame, &receivers_layout);
        let footprints = FootprintPipelines::new(device, layouts);
        let (surface_mask_layout, surface_mask) = surface_mask_pipeline(device, layouts.frame);
        let widen = shader_module(device, "GpuCulling::widen", source("GpuCulling::widen"));
        let widen_layout = bind_group_layout(
            device,
            "GpuCulling::widen_layout",
            compute,
            &[
                storage(true),
                texture(
                    wgpu::TextureSampleType::Float { filterable: false },
                    wgpu::TextureViewDimension::D2Array,
                ),
                storage(false),
                storage(false),
            ],
        );
        let widen_pipeline_layout = pipeline_layout(
            device,
            "GpuCulling::widen_pipeline_layout",
            &[&widen_layout],
        );
        let widen_pipeline =
            |entry| compute_pipeline(device, &widen, Some(&widen_pipeline_layout), entry);
        Self {
            footprint_layout: footprints.layout,
            footprint_first: footprints.first,
            footprint_second: footprints.second,
            footprint_geometry_first: footprints.geometry_first,
            footprint_geometry_second: footprints.geometry_second,
            resolve: cull("cs_resolve_footprints"),
            collect_drawn: cull("cs_collect_drawn"),
            resolve_light_visible: cull("cs_resolve_light_visible"),
            widen_layout,
            widen_rows: widen_pipeline("cs_widen_rows"),
            widen_columns: widen_pipeline("cs_widen_columns"),
            receivers: cull("cs_receivers"),
            first_phase: cull("cs_first_phase"),
            second_phase: cull("cs_second_phase"),
            far_ends: cull("cs_far_ends"),
            cull_layout,
            reduce: ReducePipelines {
                depth: reduce("cs_reduce_depth"),
                mask: reduce("cs_reduce_mask"),
                camera_depth: reduce("cs_reduce_camera_depth"),
                level: reduce("cs_reduce"),
            },
            mask_layout,
            boxes: masks.boxes,
            moved_boxes: masks.moved_boxes,
            clear_moved: masks.clear_moved,
            moved_faces: masks.moved_faces,
            clear_marked: footprints.clear_marked,
            geometry: masks.geometry,
            receivers_layout,
            fragment_mask,
            surface_mask_layout,
            surface_mask,
            oracle,
        }
    }
}

struct MaskPipelines {
    boxes: wgpu::RenderPipeline,
    moved_boxes: wgpu::RenderPipeline,
    clear_moved: wgpu::RenderPipeline,
    moved_faces: wgpu::RenderPipeline,
    geometry: Vec<wgpu::RenderPipeline>,
}

impl MaskPipelines {
    fn new(
        ctx: &GpuContext,
        layouts: &SharedLayouts<'_>,
        mask_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let device = &ctx.device;
        let module = shader_module(device, "GpuCulling::masks", source("GpuCulling::masks"));
        let layout = pipeline_layout(
            device,
            "GpuCulling::masks_layout",
            &[layouts.frame, mask_layout, layouts.pass_view],
        );
        let pipeline = |entry, with_vertices: bool, polygon_mode, conservative| {
            let vertex_buffers = [Some(VERTEX_LAYOUT)];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(entry),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
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
                    module: &module,
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
        let fill = wgpu::PolygonMode::Fill;
        let geometry = if features.contains(wgpu::Features::CONSERVATIVE_RASTERIZATION) {
            vec![pipeline("vs_geometry", true, fill, true)]
        } else if features.contains(wgpu::Features::POLYGON_MODE_LINE) {
            vec![
                pipeline("vs_geometry", true, fill, false),
                pipeline("vs_geometry", true, wgpu::PolygonMode::Line, false),
            ]
        } else {
            Vec::new()
        };
        // Incremental updates clear the changed region of the shadow map to the far plane.
        let clear_moved = depth_only_pipeline(
            device,
            &DepthOnly {
                label: "GpuCulling::clear_moved",
                layout: &layout,
                module: &module,
                entries: ("vs_clear_moved", "fs_clear"),
                vertices: false,
                cull_back: false,
                compare: wgpu::CompareFunction::Always,
                write: true,
                color: None,
            },
        );
        let moved_faces = depth_only_pipeline(
            device,
            &DepthOnly {
                label: "GpuCulling::moved_faces",
                layout: &layout,
                module: &module,
                entries: ("vs_moved_faces", "fs_mark"),
                vertices: false,
                cull_back: true,
                compare: wgpu::CompareFunction::LessEqual,
                write: false,
                color: Some(MASK_FORMAT),
            },
        );
        Self {
            moved_faces,
            boxes: pipeline("vs_box", false, fill, false),
            moved_boxes: pipeline("vs_moved_box", false, fill, false),
            clear_moved,
            geometry,
        }
    }
}

struct FootprintPipelines {
    layout: wgpu::BindGroupLayout,
    first: wgpu::RenderPipeline,
    second: wgpu::RenderPipeline,
    geometry_first: wgpu::RenderPipeline,
    geometry_second: wgpu::RenderPipeline,
    clear_marked: wgpu::RenderPipeline,
}

impl FootprintPipelines {
    /// The boxes of the candidates into one view, back faces culled, no writes: the first
    /// phase tests every texel (depth always passes), the second only the texels where the
    /// box is nearer than the map (the test forced before the shader).
    fn new(device: &wgpu::Device, layouts: &SharedLayouts<'_>) -> Self {
        let module = shader_module(
            device,
            "GpuCulling::footprints",
            source("GpuCulling::footprints"),
        );
        // The states are written by the fragment stage alone (vertex stages may not write).
        let both = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let mask_texture = texture(
            wgpu::TextureSampleType::Float { filterable: false },
            wgpu::TextureViewDimension::D2Array,
        );
        let entries = [
            layout_entry(0, both, uniform()),
            layout_entry(1, both, storage(true)),
            layout_entry(2, both, storage(true)),
            layout_entry(3, both, storage(true)),
            layout_entry(4, fragment, storage(false)),
            layout_entry(5, fragment, storage(true)),
            layout_entry(6, fragment, storage(true)),
            layout_entry(7, fragment, mask_texture),
        ];
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("GpuCulling::footprint_layout"),
            entries: &entries,
        });
        let pipeline_layout = pipeline_layout(
            device,
            "GpuCulling::footprint_pipeline_layout",
            &[layouts.frame, &layout, layouts.pass_view],
        );
        let pipeline = |label, geometry: bool, compare| {
            depth_only_pipeline(
                device,
                &DepthOnly {
                    label,
                    layout: &pipeline_layout,
                    module: &module,
                    entries: if geometry {
                        ("vs_footprint_geometry", "fs_footprint")
                    } else {
                        ("vs_footprint", "fs_footprint")
                    },
                    vertices: geometry,
                    // Boxes are closed; meshes may be open or single-sided, as in the map.
                    cull_back: !geometry,
                    compare,
                    write: false,
                    color: None,
                },
            )
        };
        let (always, less) = (wgpu::CompareFunction::Always, wgpu::CompareFunction::Less);
        // A caster's own fragments equal the map where it is front-most (and ties go either
        // way in the reference map): the geometry passes where it is not behind.
        let less_equal = wgpu::CompareFunction::LessEqual;
        let clear_marked = depth_only_pipeline(
            device,
            &DepthOnly {
                label: "GpuCulling::clear_marked",
                layout: &pipeline_layout,
                module: &module,
                entries: ("vs_square", "fs_clear_marked"),
                vertices: false,
                cull_back: false,
                compare: always,
                write: true,
                color: None,
            },
        );
        Self {
            clear_marked,
            first: pipeline("GpuCulling::footprint_first", false, always),
            second: pipeline("GpuCulling::footprint_second", false, less),
            geometry_first: pipeline("GpuCulling::footprint_geometry_first", true, always),
            geometry_second: pipeline("GpuCulling::footprint_geometry_second", true, less_equal),
            layout,
        }
    }
}

/// FRAG's mask from the surface targets (`cs_fragment_mask` in culling/receivers.wgsl): group 0
/// of scene passes and group 1 with the views' parameters, the mask and the surface.
fn surface_mask_pipeline(
    device: &wgpu::Device,
    frame_layout: &wgpu::BindGroupLayout,
) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
    let compute = wgpu::ShaderStages::COMPUTE;
    let float = wgpu::TextureSampleType::Float { filterable: false };
    let d2 = wgpu::TextureViewDimension::D2;
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("GpuCulling::surface_mask_layout"),
        entries: &[
            layout_entry(0, compute, storage(true)),
            layout_entry(1, compute, storage(false)),
            layout_entry(5, compute, texture(wgpu::TextureSampleType::Uint, d2)),
            layout_entry(6, compute, texture(float, d2)),
            layout_entry(7, compute, texture(float, d2)),
        ],
    });
    let module = shader_module(
        device,
        "GpuCulling::receivers",
        source("GpuCulling::receivers"),
    );
    let pipeline_layout = pipeline_layout(
        device,
        "GpuCulling::surface_mask_pipeline_layout",
        &[frame_layout, &layout],
    );
    let pipeline = compute_pipeline(device, &module, Some(&pipeline_layout), "cs_fragment_mask");
    (layout, pipeline)
}

/// FRAG's mask and the oracle's marks, from the camera's visible fragments: they need forced
/// early depth tests, without which FRAG has no mask and the oracle method draws every caster.
fn receiver_pipelines(
    ctx: &GpuContext,
    frame_layout: &wgpu::BindGroupLayout,
    receivers_layout: &wgpu::BindGroupLayout,
) -> (Option<wgpu::RenderPipeline>, Option<wgpu::RenderPipeline>) {
    if !ctx
        .features()
        .contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST)
    {
        return (None, None);
    }
    let device = &ctx.device;
    let module = shader_module(
        device,
        "GpuCulling::receivers",
        source("GpuCulling::receivers"),
    );
    let layout = pipeline_layout(
        device,
        "GpuCulling::receivers_pipeline_layout",
        &[frame_layout, receivers_layout],
    );
    // Depth EQUAL, no writes, no colour: exactly the camera's visible fragments.
    let pipeline = |entry| {
        camera_pipeline(
            device,
            entry,
            &layout,
            &module,
            entry,
            &[],
            (false, wgpu::CompareFunction::Equal),
        )
    };
    (
        Some(pipeline("fs_fragment_mask")),
        Some(pipeline("fs_oracle")),
    )
}

/// A pipeline on a shadow map's depth, its vertices from the shader alone, with an optional
/// colour target.
struct DepthOnly<'a> {
    label: &'a str,
    layout: &'a wgpu::PipelineLayout,
    module: &'a wgpu::ShaderModule,
    /// Vertex and fragment entry points.
    entries: (&'a str, &'a str),
    /// The scene's vertex buffer (else the vertex stage makes its own vertices).
    vertices: bool,
    cull_back: bool,
    compare: wgpu::CompareFunction,
    write: bool,
    color: Option<wgpu::TextureFormat>,
}

fn depth_only_pipeline(device: &wgpu::Device, d: &DepthOnly<'_>) -> wgpu::RenderPipeline {
    let targets = [d.color.map(Into::into)];
    let vertex_buffers = [Some(VERTEX_LAYOUT)];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(d.label),
        layout: Some(d.layout),
        vertex: wgpu::VertexState {
            module: d.module,
            entry_point: Some(d.entries.0),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: if d.vertices { &vertex_buffers } else { &[] },
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: d.cull_back.then_some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            depth_write_enabled: Some(d.write),
            depth_compare: Some(d.compare),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: d.module,
            entry_point: Some(d.entries.1),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets: if d.color.is_some() { &targets } else { &[] },
        }),
        multiview_mask: None,
        cache: None,
    })
}
