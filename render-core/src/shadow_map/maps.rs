//! The depth arrays a map technique renders its views into: the method's maps, and the
//! reference maps of every caster with caster ids that error and the oracle are measured
//! against; one layer per view. Long-lived pipelines; the textures are recreated when the
//! resolution or the number of layers changes.

use crate::gpu::{
    Asked, GpuContext, bind_group_layout, color_attachment, depth_attachment, pipeline_layout,
    shader_module, texture, view_entry,
};
use crate::scene_gpu::{DrawList, SceneGpu, VERTEX_LAYOUT};
use crate::shaders::compose;
use crate::shadow_view::{SHADOW_FORMAT, ShadowView};

/// Caster ids of the reference maps: instance index + 1, 0 where nothing was drawn.
pub const CASTER_ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// Which maps a pass draws into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapKind {
    /// The maps the selected method renders and the picture uses.
    Method,
    /// Every caster, with ids: what error and the oracle are measured against.
    Reference,
}

/// The shader of the caster passes, as the renderer and the validation test compose it.
pub(crate) fn shader_source() -> String {
    compose("shadow_map/shadow_depth.wgsl", &[])
}

/// A texture array with a view of the whole and one of each layer.
struct LayeredTexture {
    texture: wgpu::Texture,
    array: wgpu::TextureView,
    layers: Vec<wgpu::TextureView>,
}

impl LayeredTexture {
    fn new(
        ctx: &GpuContext,
        label: &str,
        format: wgpu::TextureFormat,
        (resolution, layers): (u32, u32),
    ) -> Self {
        let asked = Asked {
            what: format!(
                "the shadow maps ({label}): {layers} of {resolution} x {resolution} texels ({format:?})"
            ),
            remedy: "a smaller map (--shadow-res) or fewer cascades (--cascades)",
        };
        let texture = ctx.texture(
            &asked,
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: resolution,
                    height: resolution,
                    depth_or_array_layers: layers,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            },
        );
        let array = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(label),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let layers = (0..layers)
            .map(|layer| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(label),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: layer,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        Self {
            texture,
            array,
            layers,
        }
    }
}

/// The textures of one size.
struct Textures {
    resolution: u32,
    layers: u32,
    depth: LayeredTexture,
    reference_depth: LayeredTexture,
    reference_ids: LayeredTexture,
    /// The shading pass's group 1 (`shadow_map/light.wgsl`).
    light_group: wgpu::BindGroup,
}

/// One view's pass: its view and bind groups, and the pass's timestamps.
pub struct ViewPass<'a> {
    pub view: &'a ShadowView,
    pub frame_group: &'a wgpu::BindGroup,
    pub pass_group: &'a wgpu::BindGroup,
    pub timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'a>>,
}

/// Long-lived pipelines and the current textures.
pub struct MapArrays {
    pipeline: wgpu::RenderPipeline,
    id_pipeline: wgpu::RenderPipeline,
    light_layout: wgpu::BindGroupLayout,
    textures: Textures,
    /// Bumped when the textures are replaced.
    generation: u64,
}

impl MapArrays {
    /// `frame_layout` is group 0 of scene passes, `pass_view_layout` one view alone.
    pub fn new(
        ctx: &GpuContext,
        frame_layout: &wgpu::BindGroupLayout,
        pass_view_layout: &wgpu::BindGroupLayout,
        resolution: u32,
    ) -> Self {
        let device = &ctx.device;
        let module = shader_module(device, "ShadowMap::shader", shader_source());
        let layout = pipeline_layout(
            device,
            "ShadowMap::layout",
            &[frame_layout, pass_view_layout],
        );
        let array = wgpu::TextureViewDimension::D2Array;
        let light_layout = bind_group_layout(
            device,
            "ShadowMap::light_layout",
            wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            &[
                texture(wgpu::TextureSampleType::Depth, array),
                texture(wgpu::TextureSampleType::Depth, array),
                texture(wgpu::TextureSampleType::Uint, array),
            ],
        );
        let textures = Textures::new(ctx, &light_layout, (resolution, 1));
        Self {
            pipeline: caster_pipeline(device, &layout, &module, false),
            id_pipeline: caster_pipeline(device, &layout, &module, true),
            light_layout,
            textures,
            generation: 0,
        }
    }

    /// Recreates the textures when `resolution` or `layers` differ.
    pub fn ensure(&mut self, ctx: &GpuContext, resolution: u32, layers: u32) {
        let layers = layers.max(1);
        if (self.textures.resolution, self.textures.layers) != (resolution, layers) {
            self.textures = Textures::new(ctx, &self.light_layout, (resolution, layers));
            self.generation += 1;
        }
    }

    pub fn resolution(&self) -> u32 {
        self.textures.resolution
    }

    pub fn layers(&self) -> u32 {
        self.textures.layers
    }

    pub fn generation(&self) -> u64 {
        self.generation
    }

    pub fn light_layout(&self) -> &wgpu::BindGroupLayout {
        &self.light_layout
    }

    pub fn light_group(&self) -> &wgpu::BindGroup {
        &self.textures.light_group
    }

    /// The method's maps: every layer, and each alone.
    pub fn depth_array(&self) -> &wgpu::TextureView {
        &self.textures.depth.array
    }

    pub fn depth_layers(&self) -> &[wgpu::TextureView] {
        &self.textures.depth.layers
    }

    /// The method's depth texture (all layers).
    pub fn depth_texture(&self) -> &wgpu::Texture {
        &self.textures.depth.texture
    }

    /// The reference maps' depth and ids, every layer.
    pub fn reference_arrays(&self) -> (&wgpu::TextureView, &wgpu::TextureView) {
        (
            &self.textures.reference_depth.array,
            &self.textures.reference_ids.array,
        )
    }

    /// Layer `layer` of the method's map and of the reference's ids.
    pub fn layer(&self, layer: u32) -> Option<(&wgpu::TextureView, &wgpu::TextureView)> {
        let t = &self.textures;
        Some((
            t.depth.layers.get(layer as usize)?,
            t.reference_ids.layers.get(layer as usize)?,
        ))
    }

    /// Draws `casters` into one view of `map`, clearing its layer first: the method's maps
    /// (depth only) or the reference maps (depth and caster ids).
    pub fn draw_list(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pass: ViewPass<'_>,
        (scene_gpu, casters, indirect_first_instance): (&SceneGpu, &DrawList, bool),
        map: MapKind,
    ) {
        let Some(mut render) = self.begin(encoder, pass, map, true) else {
            return;
        };
        render.set_pipeline(match map {
            MapKind::Method => &self.pipeline,
            MapKind::Reference => &self.id_pipeline,
        });
        casters.draw(&mut render, scene_gpu, indirect_first_instance);
    }

    /// Draws into one view of the method's maps with one indirect draw per instance (`count`
    /// of them from byte `offset` of `draws`), on top of what is there unless `clear`. The GPU
    /// culling methods' passes.
    pub fn draw_indirect(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pass: ViewPass<'_>,
        scene_gpu: &SceneGpu,
        (draws, offset, count): (&wgpu::Buffer, u64, u32),
        clear: bool,
    ) {
        let Some(mut render) = self.begin(encoder, pass, MapKind::Method, clear) else {
            return;
        };
        render.set_pipeline(&self.pipeline);
        render.set_vertex_buffer(0, scene_gpu.vertex_buffer.slice(..));
        render.set_index_buffer(scene_gpu.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        render.multi_draw_indexed_indirect(draws, offset, count);
    }

    /// A pass on the view's layer, drawing in its square; `clear` clears the layer. `None`
    /// for a view whose layer the arrays do not have.
    fn begin<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        pass: ViewPass<'_>,
        map: MapKind,
        clear: bool,
    ) -> Option<wgpu::RenderPass<'e>> {
        let t = &self.textures;
        let layer = pass.view.target.layer as usize;
        let (depth, ids) = match map {
            MapKind::Method => (t.depth.layers.get(layer)?, None),
            MapKind::Reference => (
                t.reference_depth.layers.get(layer)?,
                Some(t.reference_ids.layers.get(layer)?),
            ),
        };
        let id_attachment =
            ids.map(|view| color_attachment(view, wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)));
        let mut render = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(match map {
                MapKind::Method => "ShadowMap::draw_casters",
                MapKind::Reference => "ShadowMap::draw_reference",
            }),
            color_attachments: if id_attachment.is_some() {
                std::slice::from_ref(&id_attachment)
            } else {
                &[]
            },
            depth_stencil_attachment: Some(depth_attachment(depth, clear.then_some(1.0))),
            timestamp_writes: pass.timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.view.target.set_viewport(&mut render);
        render.set_bind_group(0, pass.frame_group, &[]);
        render.set_bind_group(1, pass.pass_group, &[]);
        Some(render)
    }
}

impl Textures {
    fn new(
        ctx: &GpuContext,
        light_layout: &wgpu::BindGroupLayout,
        (resolution, layers): (u32, u32),
    ) -> Self {
        let device = &ctx.device;
        let resolution = resolution.clamp(1, device.limits().max_texture_dimension_2d);
        let layers = layers.clamp(1, device.limits().max_texture_array_layers);
        let size = (resolution, layers);
        let depth = LayeredTexture::new(ctx, "ShadowMap::depth", SHADOW_FORMAT, size);
        let reference_depth =
            LayeredTexture::new(ctx, "ShadowMap::reference_depth", SHADOW_FORMAT, size);
        let reference_ids =
            LayeredTexture::new(ctx, "ShadowMap::reference_ids", CASTER_ID_FORMAT, size);
        let light_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ShadowMap::light_group"),
            layout: light_layout,
            entries: &[
                view_entry(0, &depth.array),
                view_entry(1, &reference_depth.array),
                view_entry(2, &reference_ids.array),
            ],
        });
        Self {
            resolution,
            layers,
            depth,
            reference_depth,
            reference_ids,
            light_group,
        }
    }
}

/// Casters into a shadow view: depth only, or (`with_ids`) depth and caster ids.
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
