//! The latest error or info message, framed at the top of the panel.

use crate::theme;

pub fn ui(ui: &mut egui::Ui, text: &str) {
    egui::Frame::group(ui.style())
        .stroke(egui::Stroke::new(1.0, theme::WARNING))
        .show(ui, |ui| {
            ui.set_width(ui.available_width());
            ui.add(egui::Label::new(egui::RichText::new(text).color(theme::WARNING)).wrap());
        });
    ui.add_space(theme::SECTION_GAP);
}
