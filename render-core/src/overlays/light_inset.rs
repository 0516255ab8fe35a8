//! The light's view inset (`overlays/light_inset.wgsl`): one shadow view's map, its receiver
//! mask in Bittner's colours, and the casters the method culled, striped by stage. Long-lived
//! pipeline and texture (what the panel shows); the bind group follows what the frame drew.

use bytemuck::{Pod, Zeroable};

use crate::culling::codes;
use crate::gpu::{
    bind_group_layout, buffer_entry, color_attachment, depth_texture, fullscreen_pipeline, storage,
    texture, uniform, view_entry,
};
use crate::shaders::compose;
use crate::technique::InsetSources;
use crate::view::targets::COLOR_FORMAT;

/// Size of the light's view inset, in pixels.
pub const LIGHT_VIEW_SIZE: u32 = 256;

/// `Inset` in `light_inset.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct InsetParams {
    /// Show bits, shadow texels per mask texel, the view's first outcome and mask word.
    show: [u32; 4],
    /// The view's first texel, its side, the mask's side.
    square: [u32; 4],
}

/// Bits of `InsetParams::show[0]` (`SHOW_*` in `light_inset.wgsl`).
mod show {
    pub const RASTER_MASK: u32 = 1;
    pub const FRAGMENT_MASK: u32 = 2;
    pub const OUTCOMES: u32 = 4;
}

/// The inset's shader, as the renderer and the validation test compose it.
pub(crate) fn shader_source() -> String {
    let codes = codes::wgsl();
    let palette = crate::palette::wgsl();
    compose(
        "overlays/light_inset.wgsl",
        &[
            (codes::WGSL_PATH, codes.as_str()),
            (crate::palette::WGSL_PATH, palette.as_str()),
        ],
    )
}

pub struct LightInset {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
    /// The light's view as an sRGB image, for the panel and the `light-view` overlay.
    view: wgpu::TextureView,
    /// The same read as plain `Rgba8Unorm` (sRGB-encoded bytes), as egui displays it.
    view_unorm: wgpu::TextureView,
}

impl LightInset {
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = bind_group_layout(
            device,
            "LightInset::layout",
            wgpu::ShaderStages::FRAGMENT,
            &[
                depth_texture(),
                texture(
                    wgpu::TextureSampleType::Uint,
                    wgpu::TextureViewDimension::D2,
                ),
                storage(true),
                texture(
                    wgpu::TextureSampleType::Float { filterable: false },
                    wgpu::TextureViewDimension::D2,
                ),
                storage(true),
                uniform(),
            ],
        );
        let pipeline = fullscreen_pipeline(
            device,
            "LightInset",
            &shader_source(),
            "fs_light_view",
            &layout,
            COLOR_FORMAT.into(),
        );
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("LightInset::params"),
            size: size_of::<InsetParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("LightInset::texture"),
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
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let view_unorm = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("LightInset::texture_unorm"),
            format: Some(wgpu::TextureFormat::Rgba8Unorm),
            ..Default::default()
        });
        Self {
            layout,
            pipeline,
            params,
            view,
            view_unorm,
        }
    }

    /// The inset image as egui displays it (sRGB bytes read as `Rgba8Unorm`).
    pub fn texture_unorm(&self) -> &wgpu::TextureView {
        &self.view_unorm
    }

    /// The bind group for this frame's inset; writes its parameters.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sources: &InsetSources<'_>,
    ) -> wgpu::BindGroup {
        let bits = |on: bool, bit: u32| if on { bit } else { 0 };
        let params = InsetParams {
            show: [
                bits(sources.show_raster_mask, show::RASTER_MASK)
                    | bits(sources.show_fragment_mask, show::FRAGMENT_MASK)
                    | bits(sources.show_outcomes, show::OUTCOMES),
                sources.mask_scale.max(1),
                sources.outcomes_offset,
                sources.mask_offset,
            ],
            square: [
                sources.origin[0],
                sources.origin[1],
                sources.size,
                sources.mask_size,
            ],
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
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

    /// Draws the inset into its own texture, and where `onto` is given also into that colour
    /// target's top-left corner (the `light-view` overlay), keeping the rest of it.
    pub fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        group: &wgpu::BindGroup,
        onto: Option<(&wgpu::TextureView, u32, u32)>,
    ) {
        self.draw_into(
            encoder,
            group,
            &self.view,
            None,
            wgpu::LoadOp::Clear(wgpu::Color::BLACK),
        );
        if let Some((target, width, height)) = onto {
            let side = (LIGHT_VIEW_SIZE as f32)
                .min(width.min(height) as f32 * 0.4)
                .max(1.0);
            let margin = (side * 0.05).round();
            self.draw_into(
                encoder,
                group,
                target,
                Some([margin, margin, side, side]),
                wgpu::LoadOp::Load,
            );
        }
    }

    /// Draws into `target` (an sRGB colour view), in `viewport` if given (`[x, y, width,
    /// height]` in pixels), keeping what is outside it.
    fn draw_into(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        group: &wgpu::BindGroup,
        target: &wgpu::TextureView,
        viewport: Option<[f32; 4]>,
        load: wgpu::LoadOp<wgpu::Color>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("LightInset::draw"),
            color_attachments: &[Some(color_attachment(target, load))],
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
