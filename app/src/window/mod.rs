//! The window: winit events, egui panels, the 3D view and screenshots. The 3D view is the same
//! frame the headless CLI renders, shown in egui's central panel as a texture.

mod camera_control;
mod surface;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::mpsc;
use std::time::Instant;

use anyhow::Context as _;
use glam::Vec2;
use render_core::frame::compare::CompareAll;
use render_core::frame::{FrameInput, FrameRenderer, FrameReport, FrameSettings, SceneGpu};
use render_core::gpu::{GpuContext, read_texel, read_texture};
use render_core::scene::{ChunkSettings, Scene, SceneFacts};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::cli::{DEFAULT_FOV_DEG, OpenArgs};
use crate::headless::{stats_json, write_png};
use crate::scene_source::load_scene;
use camera_control::{CameraController, Drag, MoveKeys};
use surface::{EguiFrame, WindowSurface, read_capture};

/// Opens the window on the scene in `args` and runs until it is closed.
pub fn run(args: &OpenArgs) -> anyhow::Result<()> {
    let event_loop = EventLoop::new().context(
        "cannot open a window (no display?). On a machine without a display use `shadowlab shot` or `shadowlab bench`, \
         or run under `xvfb-run -a`",
    )?;
    let mut app = App {
        args,
        running: None,
        error: None,
    };
    event_loop
        .run_app(&mut app)
        .context("the window's event loop failed")?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

struct App<'a> {
    args: &'a OpenArgs,
    running: Option<Running>,
    error: Option<anyhow::Error>,
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match Running::new(event_loop, self.args) {
            Ok(running) => self.running = Some(running),
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(running) = &mut self.running else {
            return;
        };
        running.on_window_event(event_loop, &event);
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(running) = &self.running {
            running.window.request_redraw();
        }
    }
}

/// Everything that lives while the window is open.
struct Running {
    window: Arc<Window>,
    ctx: GpuContext,
    surface: WindowSurface,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    renderer: FrameRenderer,
    scene: Scene,
    scene_gpu: SceneGpu,
    facts: SceneFacts,
    scene_spec: String,
    seed: u64,
    chunking: ChunkSettings,
    settings: FrameSettings,
    controller: CameraController,
    keys: MoveKeys,
    alt_held: bool,
    cursor_px: Option<Vec2>,
    side_panel: ui::SidePanel,
    screenshot_settings: ui::ScreenshotSettings,
    view_texture: Option<egui::TextureId>,
    light_view_texture: egui::TextureId,
    /// The 3D view's rectangle in egui points, from the last egui pass.
    view_rect: egui::Rect,
    last_report: Option<FrameReport>,
    /// The "compare all" table's renderer while it is on.
    compare: Option<CompareAll>,
    last_frame_ms: f64,
    message: Option<String>,
    last_screenshot: Option<String>,
    file_dialog: Option<mpsc::Receiver<Option<PathBuf>>>,
    /// Where a left click started (window pixels), to tell a click from a drag.
    click_start: Option<Vec2>,
    /// The clicked instance and, when measuring, whether it was in the oracle set then.
    selected: Option<(u32, Option<bool>)>,
    screenshot_requested: bool,
    frames_presented: u64,
    exit_after_frames: Option<u64>,
    /// The smoke test's screenshot is still to be taken.
    exit_screenshot_pending: bool,
    started: Instant,
    /// Time of the scene's scripted motion; advances while "animate" is on.
    scene_time_s: f64,
    last_frame: Instant,
    fps: Option<f32>,
}

impl Running {
    fn new(event_loop: &ActiveEventLoop, args: &OpenArgs) -> anyhow::Result<Self> {
        let chunking = args.scene.chunking();
        let scene = load_scene(&args.scene.scene, args.scene.seed, chunking)?;
        let attributes = Window::default_attributes()
            .with_title(format!("shadowlab: {}", scene.name))
            .with_inner_size(winit::dpi::LogicalSize::new(1400.0, 860.0));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("creating the window")?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let wgpu_surface = instance
            .create_surface(Arc::clone(&window))
            .context("creating a GPU surface for the window")?;
        let adapter = GpuContext::request_adapter(&instance, Some(&wgpu_surface))?;
        let ctx = GpuContext::with_adapter(instance, adapter)?;
        log::info!("shadowlab window on {}", ctx.adapter_description());
        let size = window.inner_size();
        let mut surface = WindowSurface::new(&ctx, wgpu_surface, size.width, size.height)?;

        let egui_ctx = egui::Context::default();
        ui::theme::apply(&egui_ctx);
        let max_texture_side = ctx.device.limits().max_texture_dimension_2d as usize;
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(max_texture_side),
        );

        let renderer = FrameRenderer::new(&ctx);
        let light_view_texture = surface.egui_renderer.register_native_texture(
            &ctx.device,
            &renderer.shadow_map.light_view_view_unorm,
            wgpu::FilterMode::Linear,
        );
        let scene_gpu = SceneGpu::new(&ctx, &scene);
        let mut settings = args.view.settings(&scene)?;
        settings.sun = scene.sun;
        settings.compare_all = args.compare;
        if let Some(sun) = args.view.sun {
            settings.sun = render_core::scene::Sun::from_direction(sun);
        }
        let aspect = size.width.max(1) as f32 / size.height.max(1) as f32;
        let mut controller =
            CameraController::framing(&scene.bounds(), aspect, DEFAULT_FOV_DEG.to_radians());
        if args.view.eye.is_some() || args.view.target.is_some() {
            controller.camera = args.view.camera(&scene, aspect)?;
        }
        let now = Instant::now();
        Ok(Self {
            window,
            ctx,
            surface,
            egui_ctx,
            egui_state,
            renderer,
            facts: SceneFacts::from(&scene),
            scene_gpu,
            scene,
            scene_spec: args.scene.scene.clone(),
            seed: args.scene.seed,
            chunking,
            settings,
            controller,
            keys: MoveKeys::default(),
            alt_held: false,
            cursor_px: None,
            side_panel: ui::SidePanel::new(),
            screenshot_settings: match &args.screenshot_dir {
                Some(dir) => ui::ScreenshotSettings {
                    folder: dir.display().to_string(),
                    include_panel: true,
                },
                None => ui::ScreenshotSettings::default(),
            },
            view_texture: None,
            light_view_texture,
            view_rect: egui::Rect::NOTHING,
            last_report: None,
            compare: None,
            last_frame_ms: 0.0,
            message: None,
            last_screenshot: None,
            file_dialog: None,
            click_start: None,
            selected: None,
            screenshot_requested: false,
            frames_presented: 0,
            exit_after_frames: args.exit_after_frames,
            exit_screenshot_pending: args.screenshot_dir.is_some(),
            started: now,
            scene_time_s: 0.0,
            last_frame: now,
            fps: None,
        })
    }

    fn on_window_event(&mut self, event_loop: &ActiveEventLoop, event: &WindowEvent) {
        let response = self.egui_state.on_window_event(&self.window, event);
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => self.surface.resize(&self.ctx, size.width, size.height),
            WindowEvent::DroppedFile(path) => self.open_scene(&path.display().to_string()),
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            WindowEvent::ModifiersChanged(m) => {
                self.alt_held = m.state().alt_key();
                self.keys.fast = m.state().shift_key();
            }
            WindowEvent::KeyboardInput { event: key, .. }
                if !self.egui_ctx.egui_wants_keyboard_input() =>
            {
                if let PhysicalKey::Code(code) = key.physical_key {
                    self.on_key(code, key.state == ElementState::Pressed);
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                self.on_mouse_button(*button, *state == ElementState::Pressed, response.consumed);
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = Vec2::new(position.x as f32, position.y as f32);
                if let Some(before) = self.cursor_px {
                    self.controller.on_mouse_drag(now - before);
                }
                self.cursor_px = Some(now);
            }
            WindowEvent::CursorLeft { .. } => self.cursor_px = None,
            WindowEvent::MouseWheel { delta, .. } if self.cursor_over_view() => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 50.0,
                };
                self.controller.on_wheel(notches);
            }
            _ => {}
        }
    }

    fn on_key(&mut self, code: KeyCode, pressed: bool) {
        match code {
            KeyCode::KeyW => self.keys.forward = pressed,
            KeyCode::KeyS => self.keys.back = pressed,
            KeyCode::KeyA => self.keys.left = pressed,
            KeyCode::KeyD => self.keys.right = pressed,
            KeyCode::KeyE => self.keys.up = pressed,
            KeyCode::KeyQ => self.keys.down = pressed,
            KeyCode::KeyF if pressed => self.frame_scene(),
            KeyCode::F12 if pressed => self.screenshot_requested = true,
            KeyCode::Escape if pressed => self.controller.drag = Drag::None,
            _ => {}
        }
    }

    fn on_mouse_button(&mut self, button: MouseButton, pressed: bool, egui_consumed: bool) {
        if !pressed {
            self.controller.drag = Drag::None;
            // A left click that did not move selects the object under the cursor.
            if let (MouseButton::Left, Some(start), Some(now)) =
                (button, self.click_start.take(), self.cursor_px)
                && (now - start).length() < 4.0
            {
                self.select_at(now);
            }
            return;
        }
        if egui_consumed || !self.cursor_over_view() {
            return;
        }
        if button == MouseButton::Left && !self.alt_held {
            self.click_start = self.cursor_px;
        }
        self.controller.drag = match button {
            MouseButton::Right => Drag::Fly,
            MouseButton::Middle => Drag::Orbit,
            MouseButton::Left if self.alt_held => Drag::Orbit,
            _ => self.controller.drag,
        };
    }

    /// Reads the object id under `cursor_px` (window pixels) and remembers that object, or
    /// clears the selection on sky. Blocks for a one-texel readback: a click, not a frame.
    fn select_at(&mut self, cursor_px: Vec2) {
        let Some(targets) = self.renderer.targets() else {
            return;
        };
        let ppp = self.egui_ctx.pixels_per_point();
        let x = cursor_px.x - self.view_rect.min.x * ppp;
        let y = cursor_px.y - self.view_rect.min.y * ppp;
        if x < 0.0 || y < 0.0 {
            return;
        }
        match read_texel(&self.ctx, &targets.ids, x as u32, y as u32) {
            Ok(Some(bytes)) => {
                let id = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
                self.selected = id.checked_sub(1).map(|instance| {
                    let oracle = self
                        .settings
                        .measure
                        .then(|| self.renderer.read_oracle(&self.ctx, &self.scene_gpu).ok())
                        .flatten()
                        .and_then(|flags| flags.get(instance as usize).copied());
                    (instance, oracle)
                });
            }
            Ok(None) => {}
            Err(e) => {
                self.message = Some(format!("Could not read the object under the cursor: {e}"));
            }
        }
    }

    /// The selected object as the panel shows it, from the last frame's outcome.
    fn selection(&self) -> Option<ui::Selection> {
        let (instance, oracle) = self.selected?;
        let inst = self.scene.instances.get(instance as usize)?;
        let stages = self
            .last_report
            .as_ref()
            .map_or(&[][..], |r| r.stages.as_slice());
        let outcome = self.renderer.caster_outcomes().get(instance as usize)?;
        Some(ui::Selection {
            name: inst.name.clone(),
            casts_shadow: inst.casts_shadow,
            receives_shadow: inst.receives_shadow,
            visible: true,
            shadow_map: outcome.describe(stages),
            oracle,
        })
    }

    fn cursor_over_view(&self) -> bool {
        let ppp = self.egui_ctx.pixels_per_point();
        self.cursor_px
            .is_some_and(|p| self.view_rect.contains(egui::pos2(p.x / ppp, p.y / ppp)))
    }

    fn frame_scene(&mut self) {
        let aspect = self.view_rect.aspect_ratio();
        self.controller.frame(
            &self.scene.bounds(),
            if aspect.is_finite() && aspect > 0.0 {
                aspect
            } else {
                1.5
            },
        );
    }

    /// Loads a scene; on failure the current scene stays and the message names the problem.
    fn open_scene(&mut self, spec: &str) {
        match load_scene(spec, self.seed, self.chunking) {
            Ok(scene) => {
                self.scene_gpu = SceneGpu::new(&self.ctx, &scene);
                self.facts = SceneFacts::from(&scene);
                self.settings.sun = scene.sun;
                self.scene = scene;
                self.selected = None;
                spec.clone_into(&mut self.scene_spec);
                self.window
                    .set_title(&format!("shadowlab: {}", self.scene.name));
                self.frame_scene();
                self.message = Some(format!(
                    "Opened {spec}: {} objects, {} triangles",
                    self.facts.objects, self.facts.triangles
                ));
            }
            Err(e) => {
                log::error!("{e:#}");
                self.message = Some(format!(
                    "Could not open {spec}: {e:#}. The current scene stays open."
                ));
            }
        }
    }

    fn open_file_dialog(&mut self) {
        let (sender, receiver) = mpsc::channel();
        std::thread::spawn(move || {
            let picked = rfd::FileDialog::new()
                .add_filter("glTF 2.0", &["gltf", "glb"])
                .set_title("Open a glTF scene")
                .pick_file();
            // The window may have closed meanwhile; then nobody needs the answer.
            let _ = sender.send(picked);
        });
        self.file_dialog = Some(receiver);
    }

    fn poll_file_dialog(&mut self) {
        let Some(receiver) = &self.file_dialog else {
            return;
        };
        match receiver.try_recv() {
            Ok(Some(path)) => {
                self.file_dialog = None;
                self.open_scene(&path.display().to_string());
            }
            Ok(None) | Err(mpsc::TryRecvError::Disconnected) => self.file_dialog = None,
            Err(mpsc::TryRecvError::Empty) => {}
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        // Minimised or zero-sized: nothing to draw into; try again when the window has area.
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return;
        }
        if (size.width, size.height) != (self.surface.config.width, self.surface.config.height) {
            self.surface.resize(&self.ctx, size.width, size.height);
        }
        let now = Instant::now();
        let dt = now.duration_since(self.last_frame).as_secs_f32();
        self.last_frame = now;
        if dt > 0.0 {
            self.fps = Some(self.fps.map_or(1.0 / dt, |f| f * 0.9 + 0.1 / dt));
        }
        self.poll_file_dialog();
        self.controller.update(dt, self.keys);
        if self.settings.animate && !self.scene.motions.is_empty() {
            self.scene_time_s += f64::from(dt.min(0.25));
            let moved = self.scene.animate(self.scene_time_s);
            self.scene_gpu
                .update_instances(&self.ctx, &self.scene, &moved);
        }

        let egui_frame = self.run_egui();
        self.draw_view();
        let last_frame = self
            .exit_after_frames
            .is_some_and(|n| self.frames_presented + 1 >= n);
        if last_frame && self.exit_screenshot_pending {
            self.screenshot_requested = true;
        }
        let capture = (self.screenshot_requested && self.screenshot_settings.include_panel)
            .then(|| self.surface.capture_texture(&self.ctx));
        if !self.surface.paint(&self.ctx, egui_frame, capture.as_ref()) {
            // Nothing reached the screen (minimised, occluded): keep any request for next frame.
            return;
        }
        self.frames_presented += 1;
        if self.screenshot_requested {
            self.screenshot_requested = false;
            self.exit_screenshot_pending = false;
            if let Err(e) = self.save_screenshot(capture.as_ref()) {
                log::error!("screenshot failed: {e:#}");
                self.message = Some(format!("Screenshot failed: {e:#}"));
            }
        }
        if let Some(n) = self.exit_after_frames
            && self.frames_presented >= n
            && !self.exit_screenshot_pending
        {
            if let Some(png) = &self.last_screenshot {
                println!("{png} written after {} frames", self.frames_presented);
            }
            event_loop.exit();
        }
    }

    /// Runs the egui pass: side panel and the 3D view's place. Acts on what the user asked.
    fn run_egui(&mut self) -> EguiFrame {
        let raw_input = self.egui_state.take_egui_input(&self.window);
        let mut actions = Vec::new();
        let mut view_rect = self.view_rect;
        let adapter = self.ctx.adapter_description();
        let selection = self.selection();
        let input = ui::PanelInput {
            scene: &self.facts,
            report: self.last_report.as_ref(),
            light_view: Some(self.light_view_texture),
            adapter: &adapter,
            has_gpu_timestamps: self.renderer.has_gpu_timestamps(),
            last_screenshot: self.last_screenshot.as_deref(),
            message: self.message.as_deref(),
            fps: self.fps,
            selection: selection.as_ref(),
            compare: self.compare.as_ref().map(CompareAll::rows),
        };
        let view_texture = self.view_texture;
        let full_output = self.egui_ctx.run_ui(raw_input, |ui| {
            egui::Panel::left("settings")
                .default_size(330.0)
                .resizable(true)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        actions = self.side_panel.ui(
                            ui,
                            &mut self.settings,
                            &mut self.screenshot_settings,
                            &input,
                        );
                    });
                });
            egui::CentralPanel::default()
                .frame(egui::Frame::NONE)
                .show(ui, |ui| {
                    view_rect = ui.available_rect_before_wrap();
                    if let Some(id) = view_texture {
                        let uv =
                            egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
                        ui.painter().image(id, view_rect, uv, egui::Color32::WHITE);
                    }
                });
        });
        self.view_rect = view_rect;
        self.egui_state
            .handle_platform_output(&self.window, full_output.platform_output);
        for action in actions {
            match action {
                ui::UiAction::OpenFile => self.open_file_dialog(),
                ui::UiAction::Screenshot => self.screenshot_requested = true,
                ui::UiAction::FrameScene => self.frame_scene(),
                ui::UiAction::ReloadScene => {
                    let spec = self.scene_spec.clone();
                    self.open_scene(&spec);
                }
            }
        }
        EguiFrame {
            paint_jobs: self
                .egui_ctx
                .tessellate(full_output.shapes, full_output.pixels_per_point),
            textures_delta: full_output.textures_delta,
            pixels_per_point: full_output.pixels_per_point,
        }
    }

    /// Renders the 3D view at the central panel's size in pixels and hands it to egui.
    fn draw_view(&mut self) {
        let ppp = self.egui_ctx.pixels_per_point();
        let width = (self.view_rect.width() * ppp).round();
        let height = (self.view_rect.height() * ppp).round();
        if !(width >= 1.0 && height >= 1.0) {
            return;
        }
        let started = Instant::now();
        let input = FrameInput {
            camera: &self.controller.camera,
            width: width as u32,
            height: height as u32,
            settings: &self.settings,
        };
        let report = self
            .renderer
            .render(&self.ctx, &self.scene, &self.scene_gpu, &input);
        self.last_frame_ms = started.elapsed().as_secs_f64() * 1000.0;
        if self.settings.compare_all {
            let compare = self
                .compare
                .get_or_insert_with(|| CompareAll::new(&self.ctx));
            if let Err(e) = compare.step(&self.ctx, &self.scene, &self.scene_gpu, &input) {
                log::error!("compare all: {e}");
                self.message = Some(format!("Compare all stopped: {e}"));
                self.settings.compare_all = false;
            }
        } else {
            // Frees the second renderer's targets and maps.
            self.compare = None;
        }
        self.side_panel.record(
            self.started.elapsed().as_secs_f64(),
            &report,
            self.fps
                .map_or(self.last_frame_ms, |f| 1000.0 / f64::from(f)),
        );
        self.last_report = Some(report);
        if let Some(targets) = self.renderer.targets() {
            let renderer = &mut self.surface.egui_renderer;
            match self.view_texture {
                Some(id) => renderer.update_egui_texture_from_wgpu_texture(
                    &self.ctx.device,
                    &targets.color_view_unorm,
                    wgpu::FilterMode::Linear,
                    id,
                ),
                None => {
                    self.view_texture = Some(renderer.register_native_texture(
                        &self.ctx.device,
                        &targets.color_view_unorm,
                        wgpu::FilterMode::Linear,
                    ));
                }
            }
        }
    }

    /// Writes the 3D view (or, with "include panel", the whole window) as PNG plus stats JSON.
    /// Blocks for the readback: a one-off user action, not part of the frame loop.
    fn save_screenshot(&mut self, window_capture: Option<&wgpu::Texture>) -> anyhow::Result<()> {
        let report = self
            .last_report
            .as_ref()
            .context("no frame has been rendered yet")?;
        let image = if let Some(texture) = window_capture {
            read_capture(&self.ctx, texture)?
        } else {
            let targets = self
                .renderer
                .targets()
                .context("no frame has been rendered yet")?;
            read_texture(&self.ctx, &targets.color, wgpu::TextureAspect::All)?
                .into_rgba_image()
                .context("colour target is not RGBA8")?
        };
        let stamp = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        let slug: String = self
            .facts
            .name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let slug = slug
            .rsplit('_')
            .next()
            .filter(|s| !s.is_empty())
            .unwrap_or("scene")
            .to_owned();
        let folder = Path::new(&self.screenshot_settings.folder);
        let png = folder.join(format!(
            "shadowlab-{slug}-{stamp}-{}.png",
            report.frame_index
        ));
        write_png(&image, &png)?;
        let stats = stats_json(
            &self.scene,
            &self.settings,
            &self.controller.camera,
            report,
            &self.ctx,
            self.last_frame_ms,
        );
        let json_path = png.with_extension("json");
        std::fs::write(&json_path, serde_json::to_string_pretty(&stats)?)
            .with_context(|| format!("writing {}", json_path.display()))?;
        self.last_screenshot = Some(png.display().to_string());
        self.message = Some(format!(
            "Saved {} and {}",
            png.display(),
            json_path.display()
        ));
        Ok(())
    }
}
