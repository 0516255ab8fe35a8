//! The window: winit events, egui panels, the 3D view and screenshots. The 3D view is the same
//! frame the headless CLI renders, shown in egui's central panel as a texture.
//!
//! This file opens the window and runs the frame loop; `input` handles the mouse and keyboard
//! (picking included), `view` runs the egui pass and draws the 3D view, `screenshot` saves one,
//! `remembered` keeps the scene, camera and settings between runs, `exact` casts the exact
//! shadow of a still view on a worker thread while measuring.

mod camera_control;
mod exact;
mod faults;
mod frame_log;
mod input;
mod lights;
mod loading;
mod path;
mod remembered;
mod screenshot;
mod surface;
mod view;

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc;
use std::time::Instant;

use anyhow::Context as _;
use glam::Vec2;
use input::Selected;
use render_core::frame::compare::CompareAll;
use render_core::frame::{FrameRenderer, FrameReport, FrameSettings, SceneGpu};
use render_core::gpu::GpuContext;
use render_core::scene::{PointShadow, Scene, SceneFacts, Units};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

use crate::cli::{DEFAULT_FOV_DEG, DEFAULT_SCENE, OpenArgs};
use crate::scene_source::{LoadOptions, Loaded, load_scene};
use camera_control::{CameraController, MoveKeys};
use loading::Loading;
use surface::WindowSurface;

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
        None => match app.running.as_mut().and_then(|r| r.fatal.take()) {
            Some(e) => Err(e),
            None => Ok(()),
        },
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

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(running) = &self.running {
            running.remember();
        }
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
    load_options: LoadOptions,
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
    /// The exact shadow of the view, while measuring.
    exact: exact::ExactInWindow,
    /// Observing: the view whose shadows stay frozen while the camera flies outside it.
    frozen_view: Option<render_core::geom::Camera>,
    /// Recording the camera's path, playing one, the last recorded and where it was saved.
    recorder: Option<path::PathRecorder>,
    player: Option<path::PathPlayer>,
    /// The last recorded path, with the scene it was recorded in.
    recorded: Option<(String, render_core::scene::CameraPath)>,
    last_path_file: Option<String>,
    /// The "compare all" table's renderer while it is on.
    compare: Option<CompareAll>,
    last_frame_ms: f64,
    message: Option<String>,
    /// Where the scene, camera and settings are remembered (none when the system names no
    /// config folder).
    settings_file: Option<PathBuf>,
    last_screenshot: Option<String>,
    file_dialog: Option<mpsc::Receiver<Option<PathBuf>>>,
    /// A scene loading on a worker thread.
    loading: Option<Loading>,
    /// Where a left click started (window pixels), to tell a click from a drag.
    click_start: Option<Vec2>,
    /// The clicked instance and, when measuring, whether it was in the oracle set then.
    selected: Option<Selected>,
    screenshot_requested: bool,
    frames_presented: u64,
    exit_after_frames: Option<u64>,
    /// The smoke test's screenshot is still to be taken.
    exit_screenshot_pending: bool,
    /// The smoke test's scene to open after the first frame.
    then_open: Option<String>,
    started: Instant,
    /// Time of the scene's scripted motion; advances while "animate" is on.
    scene_time_s: f64,
    last_frame: Instant,
    fps: Option<f32>,
    /// `--frame-log`: a line per presented frame.
    frame_log: Option<frame_log::FrameLog>,
    /// The settings of the last frame that drew; a frame the GPU could not give memory to
    /// brings them back.
    last_good_settings: Option<FrameSettings>,
    /// `--fault-drill`: a simulated GPU fault and the view before it.
    drill: Option<faults::Drill>,
    /// Why the window closed with an error (a failed drill).
    fatal: Option<anyhow::Error>,
}

impl Running {
    fn new(event_loop: &ActiveEventLoop, args: &OpenArgs) -> anyhow::Result<Self> {
        let settings_file = remembered::settings_path();
        let mut restored = remembered::restore(args, settings_file.as_deref());
        let mut messages: Vec<String> = restored.problem.take().into_iter().collect();
        let (Loaded { scene, notes }, load_options) =
            match load_scene(&restored.spec, &restored.options) {
                Ok(loaded) => (loaded, restored.options),
                // The last scene is gone or broken: the default opens, and the panel says why.
                Err(e) if restored.spec_remembered => {
                    messages.push(format!("Could not reopen the last scene: {e:#}"));
                    DEFAULT_SCENE.clone_into(&mut restored.spec);
                    restored.camera = None;
                    restored.sun = None;
                    let options = args.scene.load_options();
                    (load_scene(DEFAULT_SCENE, &options)?, options)
                }
                Err(e) => return Err(e),
            };
        messages.extend(notes.iter().map(|n| format!("Note: {n}")));
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
        let mut surface = WindowSurface::new(&ctx, wgpu_surface)?;
        surface.resize(&ctx, size.width, size.height);

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
            renderer.light_view_texture(),
            wgpu::FilterMode::Linear,
        );
        let scene_gpu = SceneGpu::new(&ctx, &scene);
        let mut settings = args.view.settings_over(&FrameSettings {
            sun: restored.sun.unwrap_or(scene.sun),
            ..restored.frame
        })?;
        args.view.light_over(&mut settings, &scene)?;
        settings.compare_all = args.compare;
        let aspect = size.width.max(1) as f32 / size.height.max(1) as f32;
        let mut controller =
            CameraController::framing(&scene.bounds(), aspect, DEFAULT_FOV_DEG.to_radians());
        if args.view.eye.is_some() || args.view.target.is_some() {
            controller.camera = args.view.camera(&scene, aspect)?;
        } else if let Some((camera, fly_speed)) = restored.camera {
            controller.camera = camera;
            if let Some(speed) = fly_speed.filter(|s| s.is_finite() && *s > 0.0) {
                controller.fly_speed_m_per_s = speed;
            }
        }
        let frame_log = args
            .frame_log
            .as_deref()
            .map(frame_log::FrameLog::create)
            .transpose()?;
        let now = Instant::now();
        let mut running = Self {
            window,
            ctx,
            surface,
            egui_ctx,
            egui_state,
            renderer,
            facts: SceneFacts::from(&scene),
            scene_gpu,
            scene,
            scene_spec: restored.spec,
            load_options,
            settings,
            controller,
            keys: MoveKeys::default(),
            alt_held: false,
            cursor_px: None,
            side_panel: ui::SidePanel::new(),
            screenshot_settings: match (&args.screenshot_dir, restored.screenshot) {
                (Some(dir), _) => ui::ScreenshotSettings {
                    folder: dir.display().to_string(),
                    include_panel: true,
                },
                (None, Some((folder, include_panel))) => ui::ScreenshotSettings {
                    folder,
                    include_panel,
                },
                (None, None) => ui::ScreenshotSettings::default(),
            },
            view_texture: None,
            light_view_texture,
            view_rect: egui::Rect::NOTHING,
            last_report: None,
            exact: exact::ExactInWindow::new(),
            frozen_view: None,
            recorder: None,
            player: None,
            recorded: None,
            last_path_file: None,
            compare: None,
            last_frame_ms: 0.0,
            message: (!messages.is_empty()).then(|| messages.join(". ")),
            settings_file,
            last_screenshot: None,
            file_dialog: None,
            loading: None,
            click_start: None,
            selected: None,
            screenshot_requested: false,
            frames_presented: 0,
            exit_after_frames: args.exit_after_frames,
            exit_screenshot_pending: args.screenshot_dir.is_some(),
            then_open: args.then_open.clone(),
            started: now,
            scene_time_s: 0.0,
            last_frame: now,
            fps: None,
            frame_log,
            last_good_settings: None,
            drill: args.fault_drill.map(faults::Drill::Before),
            fatal: None,
        };
        if args.play_path {
            running.toggle_playing();
        }
        Ok(running)
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

    /// Starts loading a scene on a worker thread; the current one stays drawn until it is
    /// ready ([`Running::poll_loading`]). A newer request replaces an unfinished one.
    fn open_scene(&mut self, spec: &str) {
        self.open_scene_with(spec, self.load_options);
    }

    fn open_scene_with(&mut self, spec: &str, options: LoadOptions) {
        let loading = Loading::start(spec, options);
        self.message = Some(loading.progress());
        self.loading = Some(loading);
    }

    /// Installs the loading scene once it is ready; on failure the current scene stays and the
    /// message names the problem.
    fn poll_loading(&mut self) {
        let Some(loading) = &self.loading else {
            return;
        };
        let Some(result) = loading.poll() else {
            self.message = Some(loading.progress());
            return;
        };
        let spec = loading.spec.clone();
        let seconds = loading.elapsed().as_secs_f32();
        let options = loading.options;
        self.loading = None;
        match result {
            Ok(Loaded { scene, notes }) => {
                self.load_options = options;
                self.scene_gpu = SceneGpu::new(&self.ctx, &scene);
                self.facts = SceneFacts::from(&scene);
                self.settings.sun = scene.sun;
                // A point light is the scene's: the new scene's first, if it has one.
                self.settings.point_light = self
                    .settings
                    .point_light
                    .and_then(|_| PointShadow::of_scene(&scene, 0));
                self.scene = scene;
                self.exact = exact::ExactInWindow::new();
                self.frozen_view = None;
                self.selected = None;
                spec.clone_into(&mut self.scene_spec);
                self.window
                    .set_title(&format!("shadowlab: {}", self.scene.name));
                self.frame_scene();
                let opened = format!(
                    "Opened {spec} ({}) in {seconds:.1} s: {} objects, {} triangles",
                    self.load_options.units, self.facts.objects, self.facts.triangles
                );
                let notes = notes.iter().map(|n| format!("Note: {n}"));
                self.message = Some(
                    std::iter::once(opened)
                        .chain(notes)
                        .collect::<Vec<_>>()
                        .join(". "),
                );
            }
            Err(e) => {
                let message =
                    format!("Could not open {spec}: {e:#}. The current scene stays open.");
                log::error!("{message}");
                self.message = Some(message);
            }
        }
    }

    /// Reads the current scene's file again in `units`.
    pub(super) fn set_units(&mut self, units: Units) {
        let spec = self.scene_spec.clone();
        self.open_scene_with(
            &spec,
            LoadOptions {
                units,
                ..self.load_options
            },
        );
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
        let size = self.window_size();
        if size.width == 0 || size.height == 0 {
            self.drill_redraw_minimised(event_loop);
            return;
        }
        // A lost device, or memory that ran out outside a frame: recover before drawing.
        if let Some(fault) = self.ctx.take_fault() {
            self.on_gpu_fault(&fault);
            return;
        }
        if (size.width, size.height) != (self.surface.config.width, self.surface.config.height) {
            self.surface.resize(&self.ctx, size.width, size.height);
        }
        let now = Instant::now();
        let waits_before = self.ctx.waits();
        let dt = now.duration_since(self.last_frame).as_secs_f32();
        self.last_frame = now;
        if dt > 0.0 {
            self.fps = Some(self.fps.map_or(1.0 / dt, |f| f * 0.9 + 0.1 / dt));
        }
        self.poll_file_dialog();
        self.poll_loading();
        self.controller.update(dt, self.keys);
        self.follow_path(dt);
        if self.settings.animate && !self.scene.motions.is_empty() {
            self.scene_time_s += f64::from(dt.min(0.25));
            let moved = self.scene.animate(self.scene_time_s);
            self.scene_gpu
                .update_instances(&self.ctx, &self.scene, &moved);
        }

        let egui_frame = self.run_egui();
        if !self.draw_view() {
            // A new device: the next frame draws on it.
            return;
        }
        let update_ms = now.elapsed().as_secs_f64() * 1000.0;
        // The smoke test waits for a scene it is loading, and for the compare table's round.
        let settled = self.loading.is_none()
            && self.then_open.is_none()
            && (!self.settings.compare_all
                || self.compare.as_ref().is_some_and(CompareAll::complete));
        let drilled = !self.drilling();
        let last_frame = settled
            && drilled
            && self
                .exit_after_frames
                .is_some_and(|n| self.frames_presented + 1 >= n);
        if last_frame && self.exit_screenshot_pending {
            self.screenshot_requested = true;
        }
        let capture = (self.screenshot_requested && self.screenshot_settings.include_panel)
            .then(|| self.surface.capture_texture(&self.ctx));
        let painting = Instant::now();
        if !self.surface.paint(&self.ctx, egui_frame, capture.as_ref()) {
            // Nothing reached the screen (minimised, occluded): keep any request for next frame.
            return;
        }
        let paint_ms = painting.elapsed().as_secs_f64() * 1000.0;
        self.frames_presented += 1;
        let screenshot = self.screenshot_requested;
        if let Some(spec) = self.then_open.take() {
            self.open_scene(&spec);
        }
        if self.screenshot_requested {
            self.screenshot_requested = false;
            self.exit_screenshot_pending = false;
            if let Err(e) = self.save_screenshot(capture.as_ref()) {
                log::error!("screenshot failed: {e:#}");
                self.message = Some(format!("Screenshot failed: {e:#}"));
            }
        }
        self.log_frame((dt, update_ms, paint_ms), waits_before, screenshot);
        if let Err(e) = self.drill_after_frame(event_loop, settled) {
            log::error!("{e:#}");
            self.fatal = Some(e);
            event_loop.exit();
        }
        if let Some(n) = self.exit_after_frames
            && self.frames_presented >= n
            && settled
            && drilled
            && !self.exit_screenshot_pending
        {
            if let Some(png) = &self.last_screenshot {
                println!("{png} written after {} frames", self.frames_presented);
            }
            event_loop.exit();
        }
    }
}
