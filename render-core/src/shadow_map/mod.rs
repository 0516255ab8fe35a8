//! The directional shadow map: a depth texture rendered from the sun, and the texture the
//! light's view inset is drawn into (`frame/light_inset.rs`). The pass is long-lived; the depth
//! texture is recreated when the resolution changes.

use crate::frame::scene_gpu::{DrawList, SceneGpu, VERTEX_LAYOUT};
use crate::frame::targets::COLOR_FORMAT;

/// Depth of the shadow map: 0 towards the sun, 1 at the far plane.
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Size of the light's view inset, in pixels.
pub const LIGHT_VIEW_SIZE: u32 = 256;

pub(crate) const SHADOW_DEPTH_WGSL: &str = include_str!("shadow_depth.wgsl");

/// Long-lived pipelines plus the current depth texture and inset.
pub struct ShadowMapPass {
    pipeline: wgpu::RenderPipeline,
    id_pipeline: wgpu::RenderPipeline,
    /// The depth texture for fragment shaders (group layout): used by the camera's shading
    /// pass.
    pub depth_layout: wgpu::BindGroupLayout,
    pub resolution: u32,
    pub depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
    /// The light's view as an sRGB image, for the panel inset and the `light-view` overlay.
    pub light_view: wgpu::Texture,
    pub light_view_view: wgpu::TextureView,
    /// The inset read as plain `Rgba8Unorm` (sRGB-encoded bytes), as egui displays it.
    pub light_view_view_unorm: wgpu::TextureView,
    /// The current depth texture bound with [`ShadowMapPass::depth_layout`].
    pub depth_bind_group: wgpu::BindGroup,
    /// The reference map for measurements: every caster, depth and caster ids.
    pub reference: ReferenceMap,
}

/// Depth and caster ids (instance index + 1, 0 where nothing was drawn) of the reference map.
pub struct ReferenceMap {
    pub depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
    pub ids: wgpu::Texture,
    pub ids_view: wgpu::TextureView,
}

/// Which shadow map a pass draws into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapKind {
    /// The map the selected method renders and the picture uses.
    Method,
    /// Every caster, with ids: what error and the oracle are measured against.
    Reference,
}

/// Caster ids of the reference map.
pub const CASTER_ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

impl ReferenceMap {
    fn new(device: &wgpu::Device, resolution: u32) -> Self {
        let (depth, depth_view) = create_texture(
            device,
            "ShadowMap::reference_depth",
            SHADOW_FORMAT,
            resolution,
        );
        let (ids, ids_view) = create_texture(
            device,
            "ShadowMap::reference_ids",
            CASTER_ID_FORMAT,
            resolution,
        );
        Self {
            depth,
            depth_view,
            ids,
            ids_view,
        }
    }
}

impl ShadowMapPass {
    /// `frame_layout` is the camera passes' group 0 (frame uniforms and instances), declared by
    /// the WGSL in `scene_prelude`.
    pub fn new(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        scene_prelude: &str,
        resolution: u32,
    ) -> Self {
        let source = format!("{scene_prelude}\n{SHADOW_DEPTH_WGSL}");
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("ShadowMap::shader"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("ShadowMap::layout"),
            bind_group_layouts: &[Some(frame_layout)],
            immediate_size: 0,
        });
        let pipeline = caster_pipeline(device, &layout, &module, false);
        let id_pipeline = caster_pipeline(device, &layout, &module, true);

        let depth_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ShadowMap::depth_layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let (depth, depth_view) = create_depth(device, resolution);
        let light_view = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("ShadowMap::light_view"),
            size: wgpu::Extent3d {
                width: LIGHT_VIEW_SIZE,
                height: LIGHT_VIEW_SIZE,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[wgpu::TextureFormat::Rgba8Unorm],
        });
        let light_view_view = light_view.create_view(&wgpu::TextureViewDescriptor::default());
        let light_view_view_unorm = light_view.create_view(&wgpu::TextureViewDescriptor {
            label: Some("ShadowMap::light_view_unorm"),
            format: Some(wgpu::TextureFormat::Rgba8Unorm),
            ..Default::default()
        });
        let depth_bind_group = depth_bind_group(device, &depth_layout, &depth_view);
        Self {
            pipeline,
            id_pipeline,
            depth_layout,
            resolution,
            depth,
            depth_view,
            light_view,
            light_view_view,
            light_view_view_unorm,
            depth_bind_group,
            reference: ReferenceMap::new(device, resolution),
        }
    }

    /// Recreates the depth texture (and its bind group) when `resolution` differs.
    pub fn ensure_resolution(&mut self, device: &wgpu::Device, resolution: u32) {
        if resolution == self.resolution {
            return;
        }
        let (depth, depth_view) = create_depth(device, resolution);
        self.depth_bind_group = depth_bind_group(device, &self.depth_layout, &depth_view);
        self.reference = ReferenceMap::new(device, resolution);
        self.depth = depth;
        self.depth_view = depth_view;
        self.resolution = resolution;
    }

    /// Clears a map and draws `casters` into it: the method's map (depth only) or the
    /// reference map (depth and caster ids).
    #[expect(clippy::too_many_arguments, reason = "one pass, all of its inputs")]
    pub fn draw_casters(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
        frame_bind_group: &wgpu::BindGroup,
        scene_gpu: &SceneGpu,
        casters: &DrawList,
        indirect_first_instance: bool,
        map: MapKind,
    ) {
        let ids = map == MapKind::Reference;
        let mut pass = self.begin_caster_pass(encoder, timestamp_writes, map, true);
        pass.set_pipeline(if ids {
            &self.id_pipeline
        } else {
            &self.pipeline
        });
        pass.set_bind_group(0, frame_bind_group, &[]);
        casters.draw(&mut pass, scene_gpu, indirect_first_instance);
    }

    /// Draws into the method's map with one indirect draw per instance (`count` of them in
    /// `draws`), on top of what is there unless `clear`. The GPU culling methods' passes.
    #[expect(clippy::too_many_arguments, reason = "one pass, all of its inputs")]
    pub fn draw_culled(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
        frame_bind_group: &wgpu::BindGroup,
        scene_gpu: &SceneGpu,
        draws: &wgpu::Buffer,
        count: u32,
        clear: bool,
    ) {
        let mut pass = self.begin_caster_pass(encoder, timestamp_writes, MapKind::Method, clear);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame_bind_group, &[]);
        pass.set_vertex_buffer(0, scene_gpu.vertex_buffer.slice(..));
        pass.set_index_buffer(scene_gpu.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        pass.multi_draw_indexed_indirect(draws, 0, count);
    }

    fn begin_caster_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
        map: MapKind,
        clear: bool,
    ) -> wgpu::RenderPass<'e> {
        let (depth_view, ids_view) = match map {
            MapKind::Method => (&self.depth_view, None),
            MapKind::Reference => (&self.reference.depth_view, Some(&self.reference.ids_view)),
        };
        let id_attachment = ids_view.map(|view| wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                store: wgpu::StoreOp::Store,
            },
        });
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(match map {
                MapKind::Method => "ShadowMap::draw_casters",
                MapKind::Reference => "ShadowMap::draw_reference",
            }),
            color_attachments: if id_attachment.is_some() {
                std::slice::from_ref(&id_attachment)
            } else {
                &[]
            },
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: if clear {
                        wgpu::LoadOp::Clear(1.0)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}

fn create_texture(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    resolution: u32,
) -> (wgpu::Texture, wgpu::TextureView) {
    let resolution = resolution.clamp(1, device.limits().max_texture_dimension_2d);
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: resolution,
            height: resolution,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    (texture, view)
}

fn create_depth(device: &wgpu::Device, resolution: u32) -> (wgpu::Texture, wgpu::TextureView) {
    create_texture(device, "ShadowMap::depth", SHADOW_FORMAT, resolution)
}

/// Casters into a shadow map: depth only, or (`with_ids`) depth and caster ids.
fn caster_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    with_ids: bool,
) -> wgpu::RenderPipeline {
    let id_target = [Some(CASTER_ID_FORMAT.into())];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(if with_ids {
            "ShadowMap::id_pipeline"
        } else {
            "ShadowMap::pipeline"
        }),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_shadow"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[Some(VERTEX_LAYOUT)],
        },
        primitive: wgpu::PrimitiveState {
            // Both faces: imported meshes may be open or single-sided.
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: with_ids.then(|| wgpu::FragmentState {
            module,
            entry_point: Some("fs_shadow_id"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets: &id_target,
        }),
        multiview_mask: None,
        cache: None,
    })
}

fn depth_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    depth_view: &wgpu::TextureView,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("ShadowMap::depth_bind_group"),
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::TextureView(depth_view),
        }],
    })
}
