//! The overlays' legend painted into a picture, for headless shots and screenshots of the 3D
//! view alone: the window's own legend widget (`ui::legend`), laid out by an offscreen egui
//! context and drawn over the picture by egui-wgpu. A reader of a report sees what the
//! colours mean, as a user of the window does.

use anyhow::Context as _;
use render_core::frame::{FrameSettings, legend};
use render_core::gpu::{GpuContext, read_texture};
use wgpu::util::DeviceExt as _;

/// The picture's bytes are sRGB-encoded; egui paints such bytes as they are (and blends
/// them as the window does), so they go in as plain `Rgba8Unorm`.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// `image` with the legend of the overlays `settings` turn on over its bottom-left corner, as
/// the window shows it; `image` itself when no overlay is on.
pub fn with_legend(
    ctx: &GpuContext,
    image: &image::RgbaImage,
    settings: &FrameSettings,
) -> anyhow::Result<image::RgbaImage> {
    let groups = legend(settings);
    if groups.is_empty() {
        return Ok(image.clone());
    }
    let (width, height) = image.dimensions();
    let view = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(width as f32, height as f32));
    let egui_ctx = egui::Context::default();
    ui::theme::apply(&egui_ctx);
    // egui sizes a new area in its first passes (it is placed by its bottom-left corner, so
    // its size must be known) and paints it in the third; the font atlas comes with the first.
    let mut textures = egui::TexturesDelta::default();
    let mut output = None;
    for _ in 0..3 {
        let input = egui::RawInput {
            screen_rect: Some(view),
            ..Default::default()
        };
        let mut out = egui_ctx.run_ui(input, |ui| ui::legend::show(ui.ctx(), view, &groups));
        textures.append(std::mem::take(&mut out.textures_delta));
        output = Some(out);
    }
    let output = output.context("egui ran no pass")?;
    let jobs = egui_ctx.tessellate(output.shapes, output.pixels_per_point);

    let texture = ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some("legend_image::picture"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        image.as_raw(),
    );
    let mut renderer = egui_wgpu::Renderer::new(
        &ctx.device,
        FORMAT,
        egui_wgpu::RendererOptions {
            msaa_samples: 1,
            ..Default::default()
        },
    );
    for (id, deltas) in &textures.set {
        for delta in deltas {
            renderer.update_texture(&ctx.device, &ctx.queue, *id, delta);
        }
    }
    // Applied; the renderer and its textures go when this returns.
    textures.clear();
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [width, height],
        pixels_per_point: output.pixels_per_point,
    };
    let mut encoder = ctx
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("legend_image"),
        });
    let user_buffers =
        renderer.update_buffers(&ctx.device, &ctx.queue, &mut encoder, &jobs, &screen);
    let target = texture.create_view(&wgpu::TextureViewDescriptor::default());
    let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("legend_image::draw"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    renderer.render(&mut pass.forget_lifetime(), &jobs, &screen);
    ctx.queue
        .submit(user_buffers.into_iter().chain([encoder.finish()]));
    read_texture(ctx, &texture, wgpu::TextureAspect::All)?
        .into_rgba_image()
        .context("the legend's picture is not 8-bit RGBA")
}
