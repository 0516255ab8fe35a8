//! The window survives the GPU: a frame that ran out of memory (or past the device's limits)
//! brings the previous settings back; a lost device is replaced by a new one, the scene
//! uploaded again, and the camera, settings and overlays kept. `--fault-drill` simulates a
//! lost device or a minimised window and checks that the view afterwards is the view before.

use anyhow::Context as _;
use render_core::frame::{FrameRenderer, FrameSettings, SceneGpu};
use render_core::gpu::{GpuContext, GpuFault, read_texture};
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::ActiveEventLoop;

use super::Running;
use super::surface::WindowSurface;
use crate::cli::FaultDrill;

/// How many redraws a drilled minimise lasts.
const MINIMISED_REDRAWS: u32 = 4;
/// Frames before the view is read, before the fault and after the recovery: what a frame
/// draws follows what earlier frames read back (the visible receivers cascades are fitted
/// to), a few frames late.
const SETTLING_FRAMES: u64 = 5;

/// A drill's progress: the view before the fault, then the fault, then the comparison.
pub(super) enum Drill {
    Before(FaultDrill),
    /// The fault is on; `redraws` left of a minimise.
    During {
        drill: FaultDrill,
        before: image::RgbaImage,
        redraws: u32,
    },
    /// Recovered: presented frames until the view is read again.
    After {
        drill: FaultDrill,
        before: image::RgbaImage,
        frames: u64,
    },
    Done,
}

impl Running {
    /// A frame stopped by `fault`: the previous settings come back (memory, limits) or a new
    /// device replaces the lost one. The panel and the log say what happened. True when the
    /// device (and with it egui's painter) was replaced.
    pub(super) fn on_gpu_fault(&mut self, fault: &GpuFault) -> bool {
        let message = if fault.is_device_lost() {
            match self.replace_device() {
                Ok(()) => format!(
                    "{fault}. shadowlab opened a new device on {} and uploaded the scene again; \
                     the camera, the settings and the overlays are kept",
                    self.ctx.adapter_description()
                ),
                Err(e) => format!(
                    "{fault}. No new device could be opened ({e:#}); shadowlab tries again each \
                     frame. Restarting it may help"
                ),
            }
        } else {
            let previous = self.last_good_settings.unwrap_or_else(|| FrameSettings {
                sun: self.settings.sun,
                ..FrameSettings::default()
            });
            self.settings = previous;
            format!(
                "{fault}. The {} settings are back",
                if self.last_good_settings.is_some() {
                    "previous"
                } else {
                    "default"
                }
            )
        };
        log::error!("{message}");
        self.message = Some(message);
        fault.is_device_lost()
    }

    /// A new device on the window's adapter (or another one the instance finds), a new
    /// surface, renderer and egui painter on it, and the scene uploaded again.
    fn replace_device(&mut self) -> anyhow::Result<()> {
        let instance = self.ctx.instance.clone();
        let wgpu_surface = instance
            .create_surface(std::sync::Arc::clone(&self.window))
            .context("creating a GPU surface for the window")?;
        let adapter = GpuContext::request_adapter(&instance, Some(&wgpu_surface))?;
        let ctx = GpuContext::with_adapter(instance, adapter)?;
        let size = self.window.inner_size();
        // The old surface (and its swapchain) goes before the new one is configured: a
        // window has one swapchain at a time.
        drop(std::mem::replace(
            &mut self.surface,
            WindowSurface::new(&ctx, wgpu_surface)?,
        ));
        self.surface.resize(&ctx, size.width, size.height);
        let renderer = FrameRenderer::new(&ctx);
        self.light_view_texture = self.surface.egui_renderer.register_native_texture(
            &ctx.device,
            renderer.light_view_texture(),
            wgpu::FilterMode::Linear,
        );
        self.renderer = renderer;
        self.view_texture = None;
        self.scene_gpu = SceneGpu::new(&ctx, &self.scene);
        self.compare = None;
        self.exact = super::exact::ExactInWindow::new();
        // egui sends its textures (the font atlas) once; a new context sends them again.
        self.egui_ctx = egui::Context::default();
        ui::theme::apply(&self.egui_ctx);
        self.egui_state = egui_winit::State::new(
            self.egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &self.window,
            Some(self.window.scale_factor() as f32),
            None,
            Some(ctx.device.limits().max_texture_dimension_2d as usize),
        );
        self.ctx = ctx;
        log::info!(
            "shadowlab window on a new device: {}",
            self.ctx.adapter_description()
        );
        Ok(())
    }

    /// The window's size, or 0 x 0 while a drill keeps it minimised.
    pub(super) fn window_size(&self) -> PhysicalSize<u32> {
        match self.drill {
            Some(Drill::During {
                drill: FaultDrill::Minimised,
                redraws,
                ..
            }) if redraws > 0 => PhysicalSize::new(0, 0),
            _ => self.window.inner_size(),
        }
    }

    /// Whether a drill still has work (the window does not close before it is done).
    pub(super) fn drilling(&self) -> bool {
        !matches!(self.drill, None | Some(Drill::Done))
    }

    /// A redraw while a drilled minimise lasts: counts it down, and restores the window (a
    /// resize to its real size, as winit sends) when it ends.
    pub(super) fn drill_redraw_minimised(&mut self, event_loop: &ActiveEventLoop) {
        if let Some(Drill::During {
            drill: FaultDrill::Minimised,
            redraws,
            ..
        }) = &mut self.drill
        {
            *redraws = redraws.saturating_sub(1);
            if *redraws == 0 {
                let size = self.window.inner_size();
                self.on_window_event(event_loop, &WindowEvent::Resized(size));
            }
        }
    }

    /// After a presented frame: reads the view before the fault and applies it, then, a few
    /// frames after the recovery ([`SETTLING_FRAMES`]), reads it again and prints how many
    /// pixels differ.
    pub(super) fn drill_after_frame(
        &mut self,
        event_loop: &ActiveEventLoop,
        settled: bool,
    ) -> anyhow::Result<()> {
        let Some(drill) = self.drill.take() else {
            return Ok(());
        };
        self.drill = Some(match drill {
            Drill::Before(kind) if settled && self.frames_presented >= SETTLING_FRAMES => {
                let before = self.view_picture()?;
                match kind {
                    FaultDrill::DeviceLost => self.ctx.device.destroy(),
                    FaultDrill::Minimised => self.on_window_event(
                        event_loop,
                        &WindowEvent::Resized(PhysicalSize::new(0, 0)),
                    ),
                }
                println!("fault drill {kind:?}: the fault is on");
                Drill::During {
                    drill: kind,
                    before,
                    redraws: MINIMISED_REDRAWS,
                }
            }
            Drill::During {
                drill: kind,
                before,
                redraws,
            } => {
                let recovered = match kind {
                    FaultDrill::DeviceLost => self.ctx.take_fault().is_none(),
                    FaultDrill::Minimised => redraws == 0,
                };
                if recovered {
                    Drill::After {
                        drill: kind,
                        before,
                        frames: 0,
                    }
                } else {
                    Drill::During {
                        drill: kind,
                        before,
                        redraws,
                    }
                }
            }
            Drill::After {
                drill: kind,
                before,
                frames,
            } if frames >= SETTLING_FRAMES => {
                let after = self.view_picture()?;
                let differ = if before.dimensions() == after.dimensions() {
                    before
                        .pixels()
                        .zip(after.pixels())
                        .filter(|(a, b)| a != b)
                        .count()
                } else {
                    anyhow::bail!(
                        "fault drill {kind:?}: the view was {:?} before and {:?} after",
                        before.dimensions(),
                        after.dimensions()
                    );
                };
                println!(
                    "fault drill {kind:?}: recovered; the view after ({} x {}) differs from the \
                     view before in {differ} pixels",
                    after.width(),
                    after.height()
                );
                Drill::Done
            }
            Drill::After {
                drill,
                before,
                frames,
            } => Drill::After {
                drill,
                before,
                frames: frames + 1,
            },
            other => other,
        });
        Ok(())
    }

    /// The 3D view as the renderer drew it (no panel, no legend).
    fn view_picture(&self) -> anyhow::Result<image::RgbaImage> {
        let targets = self
            .renderer
            .targets()
            .context("no frame has been rendered yet")?;
        read_texture(&self.ctx, &targets.color, wgpu::TextureAspect::All)?
            .into_rgba_image()
            .context("the colour target is not RGBA8")
    }
}
