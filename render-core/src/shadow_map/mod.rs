//! The directional shadow map: a depth texture rendered from the sun, and the light's view
//! inset that shows it. The pass is long-lived; the depth texture is recreated when the
//! resolution changes.

use crate::frame::scene_gpu::{DrawList, SceneGpu, VERTEX_LAYOUT};
use crate::frame::targets::COLOR_FORMAT;

/// Depth of the shadow map: 0 towards the sun, 1 at the far plane.
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Size of the light's view inset, in pixels.
pub const LIGHT_VIEW_SIZE: u32 = 256;

pub(crate) const SHADOW_DEPTH_WGSL: &str = include_str!("shadow_depth.wgsl");
pub(crate) const LIGHT_VIEW_WGSL: &str = include_str!("light_view.wgsl");

/// Long-lived pipelines plus the current depth texture and inset.
pub struct ShadowMapPass {
    pipeline: wgpu::RenderPipeline,
    light_view_pipeline: wgpu::RenderPipeline,
    /// The depth texture for fragment shaders (group layout): used by the light's view inset
    /// and by the camera's shading pass.
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
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("ShadowMap::pipeline"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
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
            fragment: None,
            multiview_mask: None,
            cache: None,
        });

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
        let light_view_pipeline = fullscreen_pipeline(device, &depth_layout);
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
            light_view_pipeline,
            depth_layout,
            resolution,
            depth,
            depth_view,
            light_view,
            light_view_view,
            light_view_view_unorm,
            depth_bind_group,
        }
    }

    /// Recreates the depth texture (and its bind group) when `resolution` differs.
    pub fn ensure_resolution(&mut self, device: &wgpu::Device, resolution: u32) {
        if resolution == self.resolution {
            return;
        }
        let (depth, depth_view) = create_depth(device, resolution);
        self.depth_bind_group = depth_bind_group(device, &self.depth_layout, &depth_view);
        self.depth = depth;
        self.depth_view = depth_view;
        self.resolution = resolution;
    }

    /// Clears the map and draws `casters` into it.
    pub fn draw_casters(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
        frame_bind_group: &wgpu::BindGroup,
        scene_gpu: &SceneGpu,
        casters: &DrawList,
        indirect_first_instance: bool,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("ShadowMap::draw_casters"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame_bind_group, &[]);
        casters.draw(&mut pass, scene_gpu, indirect_first_instance);
    }

    /// Renders the light's view inset from the current depth texture.
    pub fn draw_light_view(&self, encoder: &mut wgpu::CommandEncoder) {
        self.draw_light_view_into(
            encoder,
            &self.light_view_view,
            None,
            wgpu::LoadOp::Clear(wgpu::Color::BLACK),
        );
    }

    /// Draws the light's view into `target` (an sRGB colour view), in `viewport` if given
    /// (`[x, y, width, height]` in pixels), keeping what is outside it.
    pub fn draw_light_view_into(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        viewport: Option<[f32; 4]>,
        load: wgpu::LoadOp<wgpu::Color>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("ShadowMap::draw_light_view"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let Some([x, y, w, h]) = viewport {
            pass.set_viewport(x, y, w, h, 0.0, 1.0);
        }
        pass.set_pipeline(&self.light_view_pipeline);
        pass.set_bind_group(0, &self.depth_bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
}

fn create_depth(device: &wgpu::Device, resolution: u32) -> (wgpu::Texture, wgpu::TextureView) {
    let resolution = resolution.clamp(1, device.limits().max_texture_dimension_2d);
    let depth = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("ShadowMap::depth"),
        size: wgpu::Extent3d {
            width: resolution,
            height: resolution,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SHADOW_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = depth.create_view(&wgpu::TextureViewDescriptor::default());
    (depth, view)
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

fn fullscreen_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("ShadowMap::light_view_shader"),
        source: wgpu::ShaderSource::Wgsl(LIGHT_VIEW_WGSL.into()),
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("ShadowMap::light_view_layout"),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("ShadowMap::light_view_pipeline"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_fullscreen"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_light_view"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets: &[Some(COLOR_FORMAT.into())],
        }),
        multiview_mask: None,
        cache: None,
    })
}
