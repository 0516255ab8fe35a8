//! The virtual maps' bind-group layouts and pipelines: the page table's compute passes
//! (`allocate.wgsl`), marking (`mark.wgsl`), per-page culling (`cull.wgsl`) and the page
//! draws (`draw.wgsl`). Long-lived.

use crate::gpu::{
    bind_group_layout, compute_pipeline, depth_texture, pipeline_layout, shader_module, storage,
    texture, uniform,
};
use crate::shaders::compose;
use crate::shadow_view::depth_pipeline;

/// The page table's passes in `allocate.wgsl`, in the order a frame runs them.
/// Marking (`mark.wgsl` `mark_pages`) runs after the first two, the fallback marks
/// (`mark_fallback`) before `allocate_fallback`.
pub(super) const TABLE_PASSES: [&str; 11] = [
    "invalidate_moved",
    "begin_pages",
    "list_free_pages",
    "allocate_pages",
    "evict_unmarked",
    "restart_free_list",
    "list_free_again",
    "allocate_refused",
    "allocate_fallback",
    "tally_pages",
    "finish_pages",
];

pub(super) fn draw_source() -> String {
    format!(
        "enable clip_distances;\n{}",
        compose("virtual_maps/draw.wgsl", &[])
    )
}

pub(super) fn compute_sources() -> [(&'static str, String); 4] {
    [
        (
            "VirtualMaps::allocate",
            compose("virtual_maps/allocate.wgsl", &[]),
        ),
        ("VirtualMaps::mark", compose("virtual_maps/mark.wgsl", &[])),
        ("VirtualMaps::cull", compose("virtual_maps/cull.wgsl", &[])),
        (
            "VirtualMaps::occlusion",
            compose("virtual_maps/occlusion.wgsl", &[]),
        ),
    ]
}

pub(super) struct Pipelines {
    pub tables_layout: wgpu::BindGroupLayout,
    pub mark_layout: wgpu::BindGroupLayout,
    pub cull_layout: wgpu::BindGroupLayout,
    pub draw_layout: wgpu::BindGroupLayout,
    pub light_layout: wgpu::BindGroupLayout,
    /// In the order of [`TABLE_PASSES`].
    pub tables: Vec<wgpu::ComputePipeline>,
    /// `mark_pages`, `mark_fallback`, `mark_sampled`, `count_sampled` and `mark_shadowed`.
    pub mark: [wgpu::ComputePipeline; 5],
    /// `cull_pages` without and with static occlusion.
    pub cull: [wgpu::ComputePipeline; 2],
    /// Static occlusion's `reduce_static`, with its group of the atlas.
    pub occlusion_layout: wgpu::BindGroupLayout,
    pub occlusion: wgpu::ComputePipeline,
    /// `None` where the adapter has no `CLIP_DISTANCES`.
    pub draws: Option<[wgpu::RenderPipeline; 2]>,
    /// When measuring, the pairs drawn again for the per-page oracle (`fs_oracle`), with its
    /// group of the oracle's texels and pairs; `None` with `draws`.
    pub oracle_layout: wgpu::BindGroupLayout,
    pub oracle: Option<wgpu::RenderPipeline>,
}

impl Pipelines {
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout, clip: bool) -> Self {
        let compute = wgpu::ShaderStages::COMPUTE;
        let mut tables_types = vec![uniform()];
        tables_types.extend([storage(false); 7]);
        tables_types.push(storage(true));
        tables_types.extend([storage(false); 4]);
        let tables_layout =
            bind_group_layout(device, "VirtualMaps::tables", compute, &tables_types);
        let float = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let mark_layout = bind_group_layout(
            device,
            "VirtualMaps::surface",
            compute,
            &[
                texture(wgpu::TextureSampleType::Uint, d2),
                texture(float, d2),
                texture(float, d2),
                storage(false),
                depth_texture(),
                storage(false),
            ],
        );
        let cull_layout = bind_group_layout(
            device,
            "VirtualMaps::cull",
            compute,
            &[storage(true), storage(true), storage(false), storage(false)],
        );
        let draw_layout = bind_group_layout(
            device,
            "VirtualMaps::draw",
            wgpu::ShaderStages::VERTEX_FRAGMENT,
            &[uniform(), storage(true), storage(true), storage(true)],
        );
        let oracle_layout = bind_group_layout(
            device,
            "VirtualMaps::oracle",
            wgpu::ShaderStages::FRAGMENT,
            &[storage(true), storage(false)],
        );
        let light_layout = bind_group_layout(
            device,
            "VirtualMaps::light",
            wgpu::ShaderStages::FRAGMENT | compute,
            &[
                uniform(),
                depth_texture(),
                storage(true),
                storage(true),
                storage(true),
            ],
        );
        let occlusion_layout = bind_group_layout(
            device,
            "VirtualMaps::occlusion",
            compute,
            &[depth_texture()],
        );
        let [allocate, mark, cull, occlusion] =
            compute_sources().map(|(label, source)| shader_module(device, label, source));
        let two = pipeline_layout(
            device,
            "VirtualMaps::tables",
            &[frame_layout, &tables_layout],
        );
        let tables = TABLE_PASSES
            .iter()
            .map(|entry| compute_pipeline(device, &allocate, Some(&two), entry))
            .collect();
        let with = |label, group: &wgpu::BindGroupLayout| {
            pipeline_layout(device, label, &[frame_layout, &tables_layout, group])
        };
        let mark_pipeline_layout = with("VirtualMaps::mark", &mark_layout);
        let mark = [
            "mark_pages",
            "mark_fallback",
            "mark_sampled",
            "count_sampled",
            "mark_shadowed",
        ]
        .map(|entry| compute_pipeline(device, &mark, Some(&mark_pipeline_layout), entry));
        let cull_pipeline_layout = with("VirtualMaps::cull", &cull_layout);
        let cull = [false, true].map(|occlusion| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("cull_pages"),
                layout: Some(&cull_pipeline_layout),
                module: &cull,
                entry_point: Some("cull_pages"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &[("STATIC_OCCLUSION", f64::from(u8::from(occlusion)))],
                    ..Default::default()
                },
                cache: None,
            })
        });
        let occlusion = compute_pipeline(
            device,
            &occlusion,
            Some(&with("VirtualMaps::occlusion", &occlusion_layout)),
            "reduce_static",
        );
        let module = clip.then(|| shader_module(device, "VirtualMaps::draw", draw_source()));
        let draws = module.as_ref().map(|module| {
            let layout =
                pipeline_layout(device, "VirtualMaps::draw", &[frame_layout, &draw_layout]);
            // The clears write the far depth whatever is there; casters as every map draws them.
            let always = (true, wgpu::CompareFunction::Always);
            let less = (false, wgpu::CompareFunction::Less);
            [
                depth_pipeline(device, (&layout, module, "vs_clear"), None, always),
                depth_pipeline(device, (&layout, module, "vs_page"), None, less),
            ]
        });
        let oracle = module.as_ref().map(|module| {
            let layout = pipeline_layout(
                device,
                "VirtualMaps::oracle",
                &[frame_layout, &draw_layout, &oracle_layout],
            );
            oracle_pipeline(device, &layout, module)
        });
        Self {
            tables_layout,
            mark_layout,
            cull_layout,
            draw_layout,
            light_layout,
            tables,
            mark,
            cull,
            occlusion_layout,
            occlusion,
            draws,
            oracle_layout,
            oracle,
        }
    }
}

/// The page draw again, its depth read with an EQUAL test and not written, `fs_oracle`
/// running only where the caster holds the texel's depth.
fn oracle_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("VirtualMaps::oracle"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_oracle"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[Some(crate::scene_gpu::VERTEX_LAYOUT)],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: crate::shadow_view::SHADOW_FORMAT,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Equal),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_oracle"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets: &[],
        }),
        multiview_mask: None,
        cache: None,
    })
}
