//! The side panel: scene facts, sun, shadow settings, light view, frame statistics, timings
//! plot and screenshots, one collapsible section each.

mod compare;
mod frame_stats;
mod grid;
mod light_view;
mod message;
mod scene;
mod screenshot;
mod selection;
mod shadows;
mod sun;
mod timings_plot;

#[cfg(test)]
mod tests;

use render_core::frame::{FrameReport, FrameSettings};

use crate::history::TimingHistory;
use crate::{PanelInput, ScreenshotSettings, UiAction, theme};

/// The lab's control and statistics panel. Long-lived: it keeps the timing history and the sun
/// angles the user set.
#[derive(Debug, Default)]
pub struct SidePanel {
    history: TimingHistory,
    sun: sun::SunEditor,
}

impl SidePanel {
    pub fn new() -> Self {
        Self::default()
    }

    /// Call once per frame with the newest report (also feeds the history plot).
    /// `time_s` is any monotonic clock in seconds; `frame_ms` the wall time of the frame.
    pub fn record(&mut self, time_s: f64, report: &FrameReport, frame_ms: f64) {
        self.history.push(time_s, frame_ms, &report.gpu);
    }

    /// The recorded frame and pass times.
    pub fn history(&self) -> &TimingHistory {
        &self.history
    }

    /// Draws the panel's contents into `ui` (the caller provides the panel and scrolling),
    /// edits `settings` and `screenshot`, and returns what the user asked for this frame.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        settings: &mut FrameSettings,
        screenshot: &mut ScreenshotSettings,
        input: &PanelInput<'_>,
    ) -> Vec<UiAction> {
        let mut actions = Vec::new();
        if let Some(text) = input.message {
            message::ui(ui, text);
        }
        section(ui, "Scene", |ui| {
            scene::ui(
                ui,
                (input.scene, input.units),
                &mut settings.animate,
                &mut actions,
            );
        });
        if let Some(selected) = input.selection {
            section(ui, "Selected object", |ui| selection::ui(ui, selected));
        }
        section(ui, "Sun", |ui| self.sun.ui(ui, &mut settings.sun));
        section(ui, "Shadows", |ui| shadows::ui(ui, settings));
        section(ui, "Compare methods", |ui| {
            compare::ui(
                ui,
                &mut settings.compare_all,
                settings.method,
                input.compare,
            );
        });
        section(ui, "Light view", |ui| light_view::ui(ui, input));
        section(ui, "Frame", |ui| {
            frame_stats::ui(ui, input, self.history.newest());
        });
        section(ui, "Timings", |ui| timings_plot::ui(ui, &self.history));
        section(ui, "Screenshot", |ui| {
            screenshot::ui(ui, screenshot, input.last_screenshot, &mut actions);
        });
        actions
    }

    /// Shows the panel on the left of `root_ui` (resizable, scrolling) and returns what the user
    /// asked for. The space left in `root_ui` afterwards is the 3D view's.
    pub fn show(
        &mut self,
        root_ui: &mut egui::Ui,
        settings: &mut FrameSettings,
        screenshot: &mut ScreenshotSettings,
        input: &PanelInput<'_>,
    ) -> Vec<UiAction> {
        egui::Panel::left("shadowlab_side_panel")
            .default_size(theme::SIDE_PANEL_WIDTH)
            .show(root_ui, |ui| {
                egui::ScrollArea::vertical()
                    .auto_shrink([false, true])
                    .show(ui, |ui| self.ui(ui, settings, screenshot, input))
                    .inner
            })
            .inner
    }
}

/// A collapsible section, open at first.
fn section(ui: &mut egui::Ui, title: &str, add_contents: impl FnOnce(&mut egui::Ui)) {
    egui::CollapsingHeader::new(egui::RichText::new(title).strong())
        .default_open(true)
        .show(ui, add_contents);
    ui.add_space(theme::SECTION_GAP);
}
