//! Screenshot folder, what to capture, and the button that asks for one.

use super::grid;
use crate::{ScreenshotSettings, UiAction, theme};

pub fn ui(
    ui: &mut egui::Ui,
    settings: &mut ScreenshotSettings,
    last_screenshot: Option<&str>,
    actions: &mut Vec<UiAction>,
) {
    grid::facts(ui, "screenshot_settings", |ui| {
        grid::labelled(
            ui,
            "Folder",
            "Where screenshots are written, relative to the working directory",
            |ui| ui.text_edit_singleline(&mut settings.folder),
        );
    });
    ui.checkbox(&mut settings.include_panel, "Include panel")
        .on_hover_text("Capture the whole window instead of the 3D view alone");
    if ui.button("Screenshot (F12)").clicked() {
        actions.push(UiAction::Screenshot);
    }
    if let Some(name) = last_screenshot {
        ui.horizontal_wrapped(|ui| {
            ui.label(egui::RichText::new("Last:").color(theme::MUTED));
            ui.label(name);
        });
    }
}
