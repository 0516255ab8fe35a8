//! The window's swapchain and the egui painter. Long-lived; reconfigured on resize and loss.

use anyhow::Context as _;
use render_core::gpu::{GpuContext, read_texture};

/// The surface, its configuration and the egui renderer that paints onto it.
pub struct WindowSurface {
    pub surface: wgpu::Surface<'static>,
    pub config: wgpu::SurfaceConfiguration,
    pub egui_renderer: egui_wgpu::Renderer,
    /// How long the last frame waited for its surface texture, submitting egui's pass and
    /// presenting, ms.
    pub last_acquire_ms: f64,
    pub last_submit_ms: f64,
    pub last_present_ms: f64,
}

/// What egui produced for one frame, ready to paint.
pub struct EguiFrame {
    pub paint_jobs: Vec<egui::ClippedPrimitive>,
    pub textures_delta: egui::TexturesDelta,
    pub pixels_per_point: f32,
}

impl WindowSurface {
    /// The surface's painter; [`Self::resize`] configures it (a window has one swapchain at a
    /// time: a surface replacing another is configured once the other is gone).
    pub fn new(ctx: &GpuContext, surface: wgpu::Surface<'static>) -> anyhow::Result<Self> {
        let caps = surface.get_capabilities(&ctx.adapter);
        let format = egui_wgpu::preferred_framebuffer_format(&caps.formats)
            .context("the window surface offers no pixel format")?;
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: 1,
            height: 1,
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        let options = egui_wgpu::RendererOptions {
            msaa_samples: 1,
            ..Default::default()
        };
        let egui_renderer = egui_wgpu::Renderer::new(&ctx.device, format, options);
        Ok(Self {
            surface,
            config,
            egui_renderer,
            last_acquire_ms: 0.0,
            last_submit_ms: 0.0,
            last_present_ms: 0.0,
        })
    }

    /// Reconfigures for a new size; a zero size (minimised) is remembered but not applied.
    pub fn resize(&mut self, ctx: &GpuContext, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&ctx.device, &self.config);
    }

    /// Paints `frame` onto the next surface texture and presents it. Also paints into
    /// `capture` (a texture of the surface format) when given. Returns false when no texture
    /// could be had this frame (minimised, occluded, outdated); the caller tries again next frame.
    pub fn paint(
        &mut self,
        ctx: &GpuContext,
        mut frame: EguiFrame,
        capture: Option<&wgpu::Texture>,
    ) -> bool {
        // egui's texture changes apply whether or not this frame reaches the screen.
        for (id, deltas) in std::mem::take(&mut frame.textures_delta.set) {
            for delta in &deltas {
                self.egui_renderer
                    .update_texture(&ctx.device, &ctx.queue, id, delta);
            }
        }
        let presented = self.paint_jobs(ctx, &frame, capture);
        for id in std::mem::take(&mut frame.textures_delta.free) {
            self.egui_renderer.free_texture(&id);
        }
        frame.textures_delta.clear();
        presented
    }

    fn paint_jobs(
        &mut self,
        ctx: &GpuContext,
        frame: &EguiFrame,
        capture: Option<&wgpu::Texture>,
    ) -> bool {
        let asked = std::time::Instant::now();
        let acquired = self.surface.get_current_texture();
        self.last_acquire_ms = asked.elapsed().as_secs_f64() * 1000.0;
        let surface_texture = match acquired {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&ctx.device, &self.config);
                return false;
            }
            wgpu::CurrentSurfaceTexture::Timeout
            | wgpu::CurrentSurfaceTexture::Occluded
            | wgpu::CurrentSurfaceTexture::Validation => {
                return false;
            }
        };
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: frame.pixels_per_point,
        };
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("WindowSurface::egui"),
            });
        let user_buffers = self.egui_renderer.update_buffers(
            &ctx.device,
            &ctx.queue,
            &mut encoder,
            &frame.paint_jobs,
            &screen,
        );
        let view = surface_texture
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let capture_view = capture.map(|t| t.create_view(&wgpu::TextureViewDescriptor::default()));
        for target in std::iter::once(&view).chain(capture_view.as_ref()) {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("WindowSurface::draw_egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.egui_renderer
                .render(&mut pass.forget_lifetime(), &frame.paint_jobs, &screen);
        }
        let submitting = std::time::Instant::now();
        ctx.queue
            .submit(user_buffers.into_iter().chain([encoder.finish()]));
        let presenting = std::time::Instant::now();
        self.last_submit_ms = presenting.duration_since(submitting).as_secs_f64() * 1000.0;
        ctx.queue.present(surface_texture);
        self.last_present_ms = presenting.elapsed().as_secs_f64() * 1000.0;
        true
    }

    /// A texture like the surface's, for [`WindowSurface::paint`] to capture the whole window.
    pub fn capture_texture(&self, ctx: &GpuContext) -> wgpu::Texture {
        ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("WindowSurface::capture"),
            size: wgpu::Extent3d {
                width: self.config.width,
                height: self.config.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.config.format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    }
}

/// Reads a captured window texture as RGBA, swapping channels for BGRA surfaces.
pub fn read_capture(ctx: &GpuContext, texture: &wgpu::Texture) -> anyhow::Result<image::RgbaImage> {
    let bgra = matches!(
        texture.format(),
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    );
    let mut rows = read_texture(ctx, texture, wgpu::TextureAspect::All)?;
    if bgra {
        for px in rows.bytes.chunks_exact_mut(4) {
            px.swap(0, 2);
        }
    }
    let mut image = rows
        .into_rgba_image()
        .context("the window capture is not 8-bit RGBA")?;
    for px in image.pixels_mut() {
        px.0[3] = 255;
    }
    Ok(image)
}
