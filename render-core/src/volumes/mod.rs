//! Stencil shadow volumes of the sun (Crow 1977; Lloyd et al., "CC Shadow Volumes", 2004):
//! exact per-pixel hard shadows, a technique with no map. Per frame:
//!
//! ```text
//! silhouettes (compute)  per caster and edge of its mesh (edges.rs), the quad's
//!                        multiplicity from its triangles' facing; per triangle, whether it
//!                        caps the volume; records appended for two indirect draws
//! volume depth           the camera's visible surface again, into a depth-stencil target
//!                        (the camera's vertex stage, so the depths are the prepass's)
//! shadow volumes         quads and caps extruded past the scene, z-fail, two-sided stencil,
//!                        depth clamped where the adapter can (nothing clipped at the far plane)
//! light term             lit where the stencil at the point's pixel is 0 (light.wgsl)
//! ```
//!
//! Every caster's volume is drawn; Lloyd's culling and clamping build on this.

pub mod edges;

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::culling::codes::{OUTCOME_NOT_CASTER, OUTCOME_RENDERED, culled_code};
use crate::culling::{CasterOutcome, Method, Stage, StageKind};
use crate::gpu::{
    AsyncReadback, GpuContext, bind_group_layout, buffer_entry, compute_pipeline, pass_label,
    pipeline_layout, shader_module, storage, texture, uniform, view_entry,
};
use crate::scene::Scene;
use crate::scene_gpu::{SceneGpu, VERTEX_LAYOUT};
use crate::shadow_view::ShadowView;
use crate::technique::{
    DrawInput, InsetSources, ShadowPasses, ShadowReport, ShadowTechnique, TechniqueInput,
};
use edges::{Edge, mesh_edges};

/// The light term's file (group 1 of the shading pass).
pub const LIGHT_WGSL: &str = "volumes/light.wgsl";

/// The volume passes' shaders: (label, WGSL), as they are built.
#[cfg(test)]
pub(crate) fn shader_sources() -> Vec<(String, String)> {
    ["volumes/find.wgsl", "volumes/draw.wgsl"]
        .map(|path| (path.to_owned(), shader_source(path)))
        .into()
}

/// A volume pass's shader, with culling's codes.
fn shader_source(path: &str) -> String {
    let codes = crate::culling::codes::wgsl();
    crate::shaders::compose(path, &[(crate::culling::codes::WGSL_PATH, codes.as_str())])
}

/// `VolumeFrame` in `volumes/common.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct VolumeFrameGpu {
    to_light: [f32; 4],
    counts: [u32; 4],
    options: [u32; 4],
}

/// `Caster` in `volumes/common.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct CasterGpu {
    instance: u32,
    first_edge: u32,
    first_triangle: u32,
    base_vertex: u32,
    edge_start: u32,
    triangle_start: u32,
    closed: u32,
    padding: u32,
}

/// Work items per workgroup of the silhouette passes.
const WORKGROUP: u32 = 64;
/// Workgroups per dispatch row.
const ROW_GROUPS: u32 = 65_535;

/// The scene as the volumes see it: every mesh's edges, the casters, room for the records.
struct SceneVolumes {
    scene_id: u64,
    excluded: Vec<u32>,
    casters: u32,
    edge_items: u32,
    triangle_items: u32,
    closed_meshes: u32,
    meshes: u32,
    scene_group: wgpu::BindGroup,
    draw_group: wgpu::BindGroup,
    quads: wgpu::Buffer,
    caps: wgpu::Buffer,
    draws: wgpu::Buffer,
    kept: wgpu::Buffer,
    receivers: wgpu::Buffer,
    counters: wgpu::Buffer,
    outcomes: wgpu::Buffer,
    instances: u32,
}

/// The depth-stencil target at the view's size and the light group that reads its stencil.
struct StencilTarget {
    size: (u32, u32),
    depth_stencil: wgpu::TextureView,
    light_group: wgpu::BindGroup,
}

/// Stencil shadow volumes of the sun: long-lived pipelines, the scene's edges and the
/// stencil target.
pub struct VolumeTechnique {
    format: wgpu::TextureFormat,
    depth_clamped: bool,
    scene_layout: wgpu::BindGroupLayout,
    find_layout: wgpu::BindGroupLayout,
    draw_layout: wgpu::BindGroupLayout,
    light_layout: wgpu::BindGroupLayout,
    reset: wgpu::ComputePipeline,
    receivers: wgpu::ComputePipeline,
    cull: wgpu::ComputePipeline,
    silhouettes: wgpu::ComputePipeline,
    caps: wgpu::ComputePipeline,
    depth: wgpu::RenderPipeline,
    quad_volumes: wgpu::RenderPipeline,
    cap_volumes: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    scene: Option<SceneVolumes>,
    target: Option<StencilTarget>,
    excluded: Vec<u32>,
    method: Method,
    /// The counters of the frames in flight, and the newest that came back: (frame, visible
    /// receivers, casters kept).
    readback: AsyncReadback,
    latest: Option<(u64, u32, u32)>,
    frame_index: u64,
}

impl VolumeTechnique {
    /// `frame_layout`: group 0 of every scene pass.
    pub fn new(ctx: &GpuContext, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let device = &ctx.device;
        let features = ctx.features();
        let format = if features.contains(wgpu::Features::DEPTH32FLOAT_STENCIL8) {
            wgpu::TextureFormat::Depth32FloatStencil8
        } else {
            wgpu::TextureFormat::Depth24PlusStencil8
        };
        let depth_clamped = features.contains(wgpu::Features::DEPTH_CLIP_CONTROL);
        let stages = wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::VERTEX;
        let scene_layout = bind_group_layout(
            device,
            "Volumes::scene_layout",
            stages,
            &[
                uniform(),
                storage(true),
                storage(true),
                storage(true),
                storage(true),
                storage(true),
            ],
        );
        let find_layout = bind_group_layout(
            device,
            "Volumes::find_layout",
            wgpu::ShaderStages::COMPUTE,
            &[
                storage(false),
                storage(false),
                storage(false),
                storage(false),
                storage(false),
                storage(false),
                storage(false),
                storage(true),
            ],
        );
        let draw_layout = bind_group_layout(
            device,
            "Volumes::draw_layout",
            wgpu::ShaderStages::VERTEX,
            &[storage(true), storage(true)],
        );
        let light_layout = bind_group_layout(
            device,
            "Volumes::light_layout",
            wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            &[texture(
                wgpu::TextureSampleType::Uint,
                wgpu::TextureViewDimension::D2,
            )],
        );
        let find_module =
            shader_module(device, "Volumes::find", shader_source("volumes/find.wgsl"));
        let find_pipeline_layout = pipeline_layout(
            device,
            "Volumes::find_pipeline_layout",
            &[frame_layout, &scene_layout, &find_layout],
        );
        let find =
            |entry| compute_pipeline(device, &find_module, Some(&find_pipeline_layout), entry);
        let depth = depth_pipeline(device, frame_layout, format);
        let draw_module =
            shader_module(device, "Volumes::draw", shader_source("volumes/draw.wgsl"));
        let draw_pipeline_layout = pipeline_layout(
            device,
            "Volumes::draw_pipeline_layout",
            &[frame_layout, &scene_layout, &draw_layout],
        );
        let volume = |entry| {
            volume_pipeline(
                device,
                (&draw_pipeline_layout, &draw_module, entry),
                format,
                depth_clamped,
            )
        };
        Self {
            format,
            depth_clamped,
            reset: find("reset_draws"),
            receivers: find("collect_receivers"),
            cull: find("cull_casters"),
            silhouettes: find("find_silhouettes"),
            caps: find("find_caps"),
            depth,
            quad_volumes: volume("vs_quad"),
            cap_volumes: volume("vs_cap"),
            uniforms: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("Volumes::uniforms"),
                size: size_of::<VolumeFrameGpu>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            scene_layout,
            find_layout,
            draw_layout,
            light_layout,
            scene: None,
            target: None,
            excluded: Vec::new(),
            method: Method::None,
            readback: AsyncReadback::new(device, "Volumes::counters_readback", 16, 3),
            latest: None,
            frame_index: 0,
        }
    }

    /// The depth-stencil format the volumes are drawn into.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Builds the scene's edges and casters when the scene (or the excluded set) changed.
    fn ensure_scene(&mut self, ctx: &GpuContext, scene: &Scene, scene_gpu: &SceneGpu) {
        if self
            .scene
            .as_ref()
            .is_some_and(|s| s.scene_id == scene_gpu.id && s.excluded == self.excluded)
        {
            return;
        }
        let device = &ctx.device;
        let mut edges: Vec<Edge> = Vec::new();
        let mut mesh_info = Vec::with_capacity(scene.meshes.len());
        let mut closed_meshes = 0;
        for mesh in &scene.meshes {
            let e = mesh_edges(&mesh.positions, &mesh.indices);
            closed_meshes += u32::from(e.closed);
            mesh_info.push((edges.len() as u32, e.edges.len() as u32, e.closed));
            edges.extend(e.edges);
        }
        let mut casters = Vec::new();
        let (mut edge_items, mut triangle_items) = (0u32, 0u32);
        let mut outcomes = vec![OUTCOME_NOT_CASTER; scene.instances.len()];
        for (i, instance) in (0u32..).zip(&scene.instances) {
            let range = scene_gpu.instance_ranges[i as usize];
            if !instance.casts_shadow || self.excluded.contains(&i) || range.index_count < 3 {
                continue;
            }
            let (first_edge, edge_count, closed) = mesh_info[instance.mesh as usize];
            outcomes[i as usize] = OUTCOME_RENDERED;
            casters.push(CasterGpu {
                instance: i,
                first_edge,
                first_triangle: range.first_index / 3,
                base_vertex: range.base_vertex as u32,
                edge_start: edge_items,
                triangle_start: triangle_items,
                closed: u32::from(closed),
                padding: 0,
            });
            edge_items += edge_count;
            triangle_items += range.index_count / 3;
        }
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let keep = |mut v: Vec<u8>| {
            if v.is_empty() {
                v.resize(16, 0);
            }
            v
        };
        let edges_buffer = init(
            "Volumes::edges",
            &keep(bytemuck::cast_slice(&edges).to_vec()),
            wgpu::BufferUsages::STORAGE,
        );
        let casters_buffer = init(
            "Volumes::casters",
            &keep(bytemuck::cast_slice(&casters).to_vec()),
            wgpu::BufferUsages::STORAGE,
        );
        // A quad at most twice per edge (an open mesh's edge between a lit and an unlit
        // triangle), a cap pair per triangle.
        let record_buffer = |label: &str, records: u32| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: u64::from(records.max(1)) * 8,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        let quads = record_buffer("Volumes::quads", edge_items.saturating_mul(2));
        let caps = record_buffer("Volumes::caps", triangle_items);
        let storage_buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let draws = storage_buffer("Volumes::draws", 32, wgpu::BufferUsages::INDIRECT);
        let kept = storage_buffer(
            "Volumes::kept",
            u64::from(casters.len() as u32) * 4,
            wgpu::BufferUsages::empty(),
        );
        let receivers = storage_buffer(
            "Volumes::receivers",
            scene.instances.len() as u64 * 32,
            wgpu::BufferUsages::empty(),
        );
        let counters = storage_buffer("Volumes::counters", 16, wgpu::BufferUsages::COPY_SRC);
        let scene_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Volumes::scene_group"),
            layout: &self.scene_layout,
            entries: &[
                buffer_entry(0, &self.uniforms),
                buffer_entry(1, &scene_gpu.vertex_buffer),
                buffer_entry(2, &scene_gpu.index_buffer),
                buffer_entry(3, &edges_buffer),
                buffer_entry(4, &casters_buffer),
                buffer_entry(5, &scene_gpu.bounds_buffer),
            ],
        });
        let draw_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Volumes::draw_group"),
            layout: &self.draw_layout,
            entries: &[buffer_entry(0, &quads), buffer_entry(1, &caps)],
        });
        self.scene = Some(SceneVolumes {
            scene_id: scene_gpu.id,
            excluded: self.excluded.clone(),
            casters: casters.len() as u32,
            edge_items,
            triangle_items,
            closed_meshes,
            meshes: scene.meshes.len() as u32,
            scene_group,
            draw_group,
            quads,
            caps,
            draws,
            kept,
            receivers,
            counters,
            outcomes: init(
                "Volumes::outcomes",
                &keep(bytemuck::cast_slice(&outcomes).to_vec()),
                wgpu::BufferUsages::STORAGE,
            ),
            instances: scene.instances.len() as u32,
        });
    }

    /// The depth-stencil target at the view's size.
    fn ensure_target(&mut self, device: &wgpu::Device, size: (u32, u32)) {
        if self.target.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("Volumes::depth_stencil"),
            size: wgpu::Extent3d {
                width: size.0.max(1),
                height: size.1.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let stencil = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("Volumes::stencil"),
            aspect: wgpu::TextureAspect::StencilOnly,
            ..Default::default()
        });
        let light_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Volumes::light_group"),
            layout: &self.light_layout,
            entries: &[view_entry(0, &stencil)],
        });
        self.target = Some(StencilTarget {
            size,
            depth_stencil: texture.create_view(&wgpu::TextureViewDescriptor::default()),
            light_group,
        });
    }
}

/// The camera's visible surface into the depth-stencil target: its vertex stage, no colour.
fn depth_pipeline(
    device: &wgpu::Device,
    frame_layout: &wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let module = shader_module(
        device,
        "Volumes::depth",
        crate::shaders::compose("view/camera_vertex.wgsl", &[]),
    );
    let layout = pipeline_layout(device, "Volumes::depth_layout", &[frame_layout]);
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("Volumes::depth"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[Some(VERTEX_LAYOUT)],
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}

/// Volume faces, both sides, z-fail: behind the visible surface a back face counts +1 and a
/// front face -1; nothing written but the stencil.
fn volume_pipeline(
    device: &wgpu::Device,
    (layout, module, entry): (&wgpu::PipelineLayout, &wgpu::ShaderModule, &str),
    format: wgpu::TextureFormat,
    depth_clamped: bool,
) -> wgpu::RenderPipeline {
    let face = |depth_fail_op| wgpu::StencilFaceState {
        compare: wgpu::CompareFunction::Always,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op,
        pass_op: wgpu::StencilOperation::Keep,
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(entry),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: None,
            unclipped_depth: depth_clamped,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: wgpu::StencilState {
                front: face(wgpu::StencilOperation::DecrementWrap),
                back: face(wgpu::StencilOperation::IncrementWrap),
                read_mask: 0xff,
                write_mask: 0xff,
            },
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}

/// Workgroups for `items` work items, in rows of [`ROW_GROUPS`].
fn dispatch_size(items: u32) -> (u32, u32) {
    let groups = items.div_ceil(WORKGROUP);
    if groups <= ROW_GROUPS {
        (groups, 1)
    } else {
        (ROW_GROUPS, groups.div_ceil(ROW_GROUPS))
    }
}

impl ShadowTechnique for VolumeTechnique {
    fn name(&self) -> &'static str {
        "volumes"
    }

    fn light_term(&self) -> (&'static str, &wgpu::BindGroupLayout) {
        (LIGHT_WGSL, &self.light_layout)
    }

    /// `none` draws every caster's volume (standard shadow volumes); every other method culls
    /// them by the visible receivers' boxes (BVOL's test on the volumes, Lloyd's 3.1).
    fn effective_method(&self, requested: Method) -> Method {
        if requested == Method::None {
            Method::None
        } else {
            Method::Bvol
        }
    }

    fn prepare(&mut self, ctx: &GpuContext, input: &TechniqueInput<'_>) -> Vec<ShadowView> {
        self.ensure_scene(ctx, input.scene, input.scene_gpu);
        self.method = self.effective_method(input.method);
        self.frame_index = input.frame_index;
        let bounds = input.scene.bounds();
        let reach = if bounds.is_empty() {
            1.0
        } else {
            bounds.extent().length() * 1.01 + 1.0
        };
        let to_light = input.direction_to_sun.normalize_or(glam::Vec3::Y);
        let scene = self.scene.as_ref().expect("ensured above");
        ctx.queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&VolumeFrameGpu {
                to_light: to_light.extend(reach).to_array(),
                counts: [
                    scene.edge_items,
                    scene.triangle_items,
                    scene.casters,
                    culled_code(StageKind::ReceiverMask),
                ],
                options: [
                    scene.instances,
                    u32::from(self.method != Method::None),
                    0,
                    0,
                ],
            }),
        );
        Vec::new()
    }

    fn draw(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
    ) -> ShadowPasses {
        self.ensure_target(&draw.ctx.device, (draw.targets.width, draw.targets.height));
        let (Some(scene), Some(target)) = (self.scene.as_ref(), self.target.as_ref()) else {
            unreachable!("ensured in prepare and above");
        };
        let find_group = draw
            .ctx
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("Volumes::find_group"),
                layout: &self.find_layout,
                entries: &[
                    buffer_entry(0, &scene.quads),
                    buffer_entry(1, &scene.caps),
                    buffer_entry(2, &scene.draws),
                    buffer_entry(3, &scene.kept),
                    buffer_entry(4, &scene.receivers),
                    buffer_entry(5, &scene.counters),
                    buffer_entry(6, &scene.outcomes),
                    buffer_entry(7, draw.visible_flags),
                ],
            });
        let query = draw
            .timer
            .begin_scope(pass_label::VOLUME_SILHOUETTES, encoder);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("Volumes::silhouettes"),
                timestamp_writes: None,
            });
            pass.set_bind_group(0, draw.frame_group, &[]);
            pass.set_bind_group(1, &scene.scene_group, &[]);
            pass.set_bind_group(2, &find_group, &[]);
            pass.set_pipeline(&self.reset);
            pass.dispatch_workgroups(1, 1, 1);
            for (pipeline, items) in [
                (&self.receivers, scene.instances),
                (&self.cull, scene.casters),
                (&self.silhouettes, scene.edge_items),
                (&self.caps, scene.triangle_items),
            ] {
                if items > 0 {
                    let (x, y) = dispatch_size(items);
                    pass.set_pipeline(pipeline);
                    pass.dispatch_workgroups(x, y, 1);
                }
            }
        }
        draw.timer.end_pass(encoder, query);
        self.readback
            .copy(encoder, &scene.counters, input.frame_index);
        let query = draw.timer.begin_pass(pass_label::VOLUME_DEPTH, encoder);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("Volumes::depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.depth_stencil,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0),
                        store: wgpu::StoreOp::Store,
                    }),
                }),
                timestamp_writes: query
                    .as_ref()
                    .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.depth);
            pass.set_bind_group(0, draw.frame_group, &[]);
            draw.camera_draws
                .draw(&mut pass, input.scene_gpu, draw.indirect_first_instance);
        }
        draw.timer.end_pass(encoder, query);
        let query = draw.timer.begin_pass(pass_label::SHADOW_VOLUMES, encoder);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("Volumes::stencil"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.depth_stencil,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                }),
                timestamp_writes: query
                    .as_ref()
                    .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, draw.frame_group, &[]);
            pass.set_bind_group(1, &scene.scene_group, &[]);
            pass.set_bind_group(2, &scene.draw_group, &[]);
            pass.set_pipeline(&self.quad_volumes);
            pass.draw_indirect(&scene.draws, 0);
            pass.set_pipeline(&self.cap_volumes);
            pass.draw_indirect(&scene.draws, 16);
        }
        draw.timer.end_pass(encoder, query);
        ShadowPasses {
            light_group: target.light_group.clone(),
            outcomes: scene.outcomes.clone(),
        }
    }

    fn after_submit(&mut self) {
        self.readback.map_copied();
    }

    fn collect(&mut self) -> ShadowReport {
        if let Some((frame, bytes)) = self.readback.take_latest() {
            let words: &[u32] = bytemuck::cast_slice(&bytes);
            self.latest = Some((frame, words[0], words[1]));
        }
        let Some(scene) = self.scene.as_ref() else {
            return ShadowReport::default();
        };
        let kept = self.latest.map(|(_, _, kept)| kept);
        let mut stages = vec![Stage::new("scene casters", scene.casters)];
        if self.method != Method::None {
            stages.push(Stage::new(
                "visible receivers' boxes (volume)",
                kept.unwrap_or(scene.casters),
            ));
        }
        let drawn = match self.method {
            Method::None => "every caster's volume drawn",
            _ => "the volumes that reach a visible receiver's box drawn",
        };
        let mut notes = vec![format!(
            "shadow volumes: {drawn}, z-fail ({} of {} meshes closed; the others cast from both \
             sides)",
            scene.closed_meshes, scene.meshes
        )];
        if !self.depth_clamped {
            notes.push(
                "this adapter has no DEPTH_CLIP_CONTROL: volumes past the far plane are clipped"
                    .into(),
            );
        }
        ShadowReport {
            casters_total: scene.casters,
            casters_rendered: Some(match self.method {
                Method::None => scene.casters,
                _ => kept.unwrap_or(scene.casters),
            }),
            stages,
            culled_frame_index: self.latest.map(|(frame, _, _)| frame),
            notes,
            ..ShadowReport::default()
        }
    }

    fn has_results_of(&self, frame_index: u64) -> bool {
        self.latest
            .is_some_and(|(frame, _, _)| frame >= frame_index)
    }

    fn inset(&self, _view: u32) -> Option<InsetSources<'_>> {
        None
    }

    fn view_outcomes(&self) -> Vec<&[CasterOutcome]> {
        Vec::new()
    }

    fn exclude(&mut self, instances: &[u32]) {
        self.excluded = instances.to_vec();
        self.excluded.sort_unstable();
    }
}
