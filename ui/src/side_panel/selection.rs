//! The object the user clicked: what it is and why it was drawn into the shadow map or culled.

use super::grid;
use crate::Selection;

fn yes_no(value: bool) -> &'static str {
    if value { "yes" } else { "no" }
}

pub fn ui(ui: &mut egui::Ui, selection: &Selection) {
    grid::facts(ui, "selection", |ui| {
        grid::row(ui, "Object", selection.name.as_str());
        grid::row(
            ui,
            "Casts / receives",
            format!(
                "{} / {}",
                yes_no(selection.casts_shadow),
                yes_no(selection.receives_shadow)
            ),
        );
        grid::row(
            ui,
            "Visible receiver",
            yes_no(selection.visible && selection.receives_shadow),
        );
        grid::row(ui, "Shadow map", selection.shadow_map.as_str());
        if let Some(oracle) = selection.oracle {
            grid::row(ui, "Needed (oracle)", yes_no(oracle));
        }
    });
}
