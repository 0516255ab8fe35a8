//! The light's view inset (`frame/light_inset.wgsl`): the method's shadow map, its receiver mask
//! in Bittner's colours, and the casters the method culled, striped by stage. Long-lived
//! pipeline; the bind group follows what the frame drew.

use crate::frame::targets::COLOR_FORMAT;
use crate::gpu::{buffer_entry, fullscreen_pipeline, view_entry};

const LIGHT_INSET_WGSL: &str = include_str!("light_inset.wgsl");

/// Bits of the inset's `inset.x` (keep in sync with `light_inset.wgsl`).
pub(crate) mod show {
    pub const RASTER_MASK: u32 = 1;
    pub const FRAGMENT_MASK: u32 = 2;
    pub const OUTCOMES: u32 = 4;
}

/// What one frame's inset reads.
pub(crate) struct InsetSources<'a> {
    pub shadow_depth: &'a wgpu::TextureView,
    /// The reference map's caster ids; read when `show` has [`show::OUTCOMES`].
    pub reference_ids: &'a wgpu::TextureView,
    /// Per-instance outcome codes (low byte).
    pub outcomes: &'a wgpu::Buffer,
    pub mask_raster: &'a wgpu::TextureView,
    pub mask_bits: &'a wgpu::Buffer,
    /// [`show`] bits and shadow texels per mask texel.
    pub show: u32,
    pub mask_scale: u32,
}

pub(crate) struct LightInset {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
}

impl LightInset {
    pub fn new(device: &wgpu::Device) -> Self {
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty,
            count: None,
        };
        let texture = |sample_type| wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        };
        let buffer = |ty| wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let storage = wgpu::BufferBindingType::Storage { read_only: true };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("LightInset::layout"),
            entries: &[
                entry(0, texture(wgpu::TextureSampleType::Depth)),
                entry(1, texture(wgpu::TextureSampleType::Uint)),
                entry(2, buffer(storage)),
                entry(
                    3,
                    texture(wgpu::TextureSampleType::Float { filterable: false }),
                ),
                entry(4, buffer(storage)),
                entry(5, buffer(wgpu::BufferBindingType::Uniform)),
            ],
        });
        let pipeline = fullscreen_pipeline(
            device,
            "LightInset",
            LIGHT_INSET_WGSL,
            "fs_light_view",
            &layout,
            COLOR_FORMAT.into(),
        );
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("LightInset::params"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            layout,
            pipeline,
            params,
        }
    }

    /// The bind group for this frame's inset; writes its parameters.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sources: &InsetSources<'_>,
    ) -> wgpu::BindGroup {
        queue.write_buffer(
            &self.params,
            0,
            bytemuck::cast_slice(&[sources.show, sources.mask_scale.max(1), 0u32, 0]),
        );
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("LightInset::bind_group"),
            layout: &self.layout,
            entries: &[
                view_entry(0, sources.shadow_depth),
                view_entry(1, sources.reference_ids),
                buffer_entry(2, sources.outcomes),
                view_entry(3, sources.mask_raster),
                buffer_entry(4, sources.mask_bits),
                buffer_entry(5, &self.params),
            ],
        })
    }

    /// Draws the inset into `target` (an sRGB colour view), in `viewport` if given
    /// (`[x, y, width, height]` in pixels), keeping what is outside it.
    pub fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        group: &wgpu::BindGroup,
        target: &wgpu::TextureView,
        viewport: Option<[f32; 4]>,
        load: wgpu::LoadOp<wgpu::Color>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("LightInset::draw"),
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
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
    }
}
