//! The per-frame egui pass (the side panel's input, the actions it returns) and the 3D view:
//! rendered at the central panel's size and registered with egui as a texture.

use std::time::Instant;

use render_core::frame::compare::CompareAll;
use render_core::frame::{FrameInput, FrameSettings};
use render_core::geom::Camera;

use super::Running;
use super::exact::ViewOf;
use super::surface::EguiFrame;

impl Running {
    /// Runs the egui pass: side panel and the 3D view's place. Acts on what the user asked.
    pub(super) fn run_egui(&mut self) -> EguiFrame {
        let raw_input = self.egui_state.take_egui_input(&self.window);
        let mut actions = Vec::new();
        let mut view_rect = self.view_rect;
        let adapter = self.ctx.adapter_description();
        let selection = self.selection();
        let settings_file = self.settings_file.as_ref().map(|p| p.display().to_string());
        let input = ui::PanelInput {
            scene: &self.facts,
            lights: &self.scene.lights,
            units: self.load_options.units,
            report: self.last_report.as_ref(),
            light_view: Some(self.light_view_texture),
            adapter: &adapter,
            has_gpu_timestamps: self.renderer.has_gpu_timestamps(),
            last_screenshot: self.last_screenshot.as_deref(),
            message: self.message.as_deref(),
            fps: self.fps,
            selection: selection.as_ref(),
            compare: self.compare.as_ref().map(CompareAll::rows),
            settings_file: settings_file.as_deref(),
            path: ui::PathState {
                recording_keys: self.recorder.as_ref().map(super::path::PathRecorder::len),
                playing: self.player.as_ref().map(super::path::PathPlayer::name),
                last_saved: self.last_path_file.as_deref(),
            },
        };
        let view_texture = self.view_texture;
        let full_output = self.egui_ctx.run_ui(raw_input, |ui| {
            actions = self.side_panel.show(
                ui,
                &mut self.settings,
                &mut self.screenshot_settings,
                &input,
            );
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
            self.side_panel
                .show_over_view(ui.ctx(), view_rect, &self.settings);
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
                ui::UiAction::SetUnits(units) => self.set_units(units),
                ui::UiAction::ResetSettings => self.reset_settings(),
                ui::UiAction::ToggleObserver => self.toggle_observer(),
                ui::UiAction::AddSpotLight => self.add_spot_light(),
                ui::UiAction::RemoveLight(i) => self.remove_light(i),
                ui::UiAction::MoveLight(i, position) => {
                    self.move_light(i, position.metres().into());
                }
                ui::UiAction::RecordPath => self.toggle_recording(),
                ui::UiAction::PlayPath => self.toggle_playing(),
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

    /// Renders the 3D view at the central panel's size in pixels and hands it to egui. False
    /// when the device was lost and replaced: this frame's egui output belongs to the old one.
    pub(super) fn draw_view(&mut self) -> bool {
        let ppp = self.egui_ctx.pixels_per_point();
        let width = (self.view_rect.width() * ppp).round();
        let height = (self.view_rect.height() * ppp).round();
        if !(width >= 1.0 && height >= 1.0) {
            return true;
        }
        let started = Instant::now();
        // Observing: the frozen view's shadows, seen from the camera the user flies.
        let (camera, settings) = match self.frozen_view {
            Some(frozen) => (
                frozen,
                FrameSettings {
                    observer: Some(self.controller.camera),
                    ..self.settings
                },
            ),
            None => (self.controller.camera, self.settings),
        };
        let input = FrameInput {
            camera: &camera,
            width: width as u32,
            height: height as u32,
            settings: &settings,
        };
        let mut report = self
            .renderer
            .render(&self.ctx, &self.scene, &self.scene_gpu, &input);
        self.last_frame_ms = started.elapsed().as_secs_f64() * 1000.0;
        if let Some(fault) = report.fault.take() {
            return !self.on_gpu_fault(&fault);
        }
        self.last_good_settings = Some(self.settings);
        let view = ViewOf {
            camera,
            size: (input.width, input.height),
            light: self.settings.shadow_light(),
        };
        if let Err(e) = self.exact.poll() {
            log::error!("exact shadow: {e}");
            self.message = Some(format!("Could not compare with the exact shadow: {e}"));
        }
        if settings.exact_truth_applies() {
            let pending = self
                .exact
                .after_frame(&self.scene, view, &settings)
                .and_then(|exact| self.renderer.request_light_at(&self.ctx, &exact.points));
            if let Some(pending) = pending {
                self.exact.comparing(&settings, pending);
            }
            report.exact_error = self.exact.error_of(view, &settings);
        }
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
        true
    }
}

impl Running {
    /// Freezes the view and puts the camera behind and above it, or goes back to the view.
    pub(super) fn toggle_observer(&mut self) {
        if let Some(frozen) = self.frozen_view.take() {
            self.controller.camera = frozen;
            self.message = Some("Back to the view".to_owned());
            return;
        }
        let view = self.controller.camera;
        self.frozen_view = Some(view);
        let back = (self.scene.bounds().diagonal_length() * 0.1).clamp(5.0, 300.0);
        let (_, up) = view.basis();
        let eye = view.eye - view.forward * back + up * (back * 0.6);
        self.controller.camera = Camera::look_at(
            eye,
            view.eye + view.forward * back,
            view.fov_y_rad,
            view.near_m,
            view.far_m.max(back * 8.0),
        )
        .with_up(view.world_up);
        self.message = Some(
            "Observer camera: the view is frozen. White: its frustum; colours: each shadow \
             view's light box and where its cascade ends. X goes back"
                .to_owned(),
        );
    }
}
