//! Scene facts and the buttons that load or frame a scene.

use render_core::scene::{SceneFacts, Units};

use super::grid;
use crate::format::{length, point, thousands};
use crate::{PathState, UiAction};

pub fn ui(
    ui: &mut egui::Ui,
    (facts, units): (&SceneFacts, Units),
    animate: &mut bool,
    actions: &mut Vec<UiAction>,
) {
    grid::facts(ui, "scene_facts", |ui| {
        grid::row(ui, "Name", facts.name.as_str());
        grid::row(ui, "Objects", thousands(facts.objects as u64));
        grid::row(ui, "Meshes", thousands(facts.meshes as u64));
        grid::row(ui, "Triangles", thousands(facts.triangles as u64));
        grid::row(ui, "Casters", thousands(facts.casters as u64));
        if facts.lights > 0 {
            // The first casts shadow volumes when chosen (the Sun section); spot lights
            // shine every way.
            grid::row(ui, "Point / spot lights", thousands(facts.lights as u64));
        }
        bounds_rows(ui, facts.bounds_min_m, facts.bounds_max_m);
        ui.label(egui::RichText::new("Units").color(crate::theme::MUTED));
        let builtin = facts.name.starts_with("builtin:");
        ui.add_enabled_ui(!builtin, |ui| {
            let mut chosen = units;
            egui::ComboBox::from_id_salt("scene_units")
                .selected_text(units.name())
                .show_ui(ui, |ui| {
                    for u in Units::ALL {
                        ui.selectable_value(&mut chosen, u, u.name());
                    }
                })
                .response
                .on_hover_text(if builtin {
                    "Built-in scenes are in metres"
                } else {
                    "The unit of the file's coordinates; the scene loads again in metres"
                });
            if chosen != units {
                actions.push(UiAction::SetUnits(chosen));
            }
        });
        ui.end_row();
    });
    ui.checkbox(animate, "Animate dynamic objects")
        .on_hover_text(
            "Dynamic objects follow their scripted motion: the city's cars drive along their lanes",
        );
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Open glTF…")
            .on_hover_text("Load a .gltf or .glb file")
            .clicked()
        {
            actions.push(UiAction::OpenFile);
        }
        if ui
            .button("Frame scene (F)")
            .on_hover_text("Move the camera so the whole scene is in view")
            .clicked()
        {
            actions.push(UiAction::FrameScene);
        }
        if ui
            .button("Reload")
            .on_hover_text("Load the scene again from its source")
            .clicked()
        {
            actions.push(UiAction::ReloadScene);
        }
    });
}

/// Recording the camera's path while flying, and playing one back.
pub fn path_ui(ui: &mut egui::Ui, path: &PathState<'_>, actions: &mut Vec<UiAction>) {
    ui.horizontal_wrapped(|ui| {
        let record = match path.recording_keys {
            Some(keys) => format!("Stop recording ({keys} keys)"),
            None => "Record path".to_owned(),
        };
        if ui
            .button(record)
            .on_hover_text(
                "Record the camera while you fly (a key every 0.1 s); stopping saves it as CSV \
                 beside the screenshots, for `shadowlab bench --path` and `report --path`",
            )
            .clicked()
        {
            actions.push(UiAction::RecordPath);
        }
        let play = if path.playing.is_some() {
            "Stop playing"
        } else {
            "Play path"
        };
        let hover = match path.last_saved {
            Some(file) => {
                format!("Fly the last recorded path (saved as {file}), else the scene's own")
            }
            None => "Fly the last recorded path, else the scene's own".to_owned(),
        };
        if ui.button(play).on_hover_text(hover).clicked() {
            actions.push(UiAction::PlayPath);
        }
        if let Some(name) = path.playing {
            ui.label(egui::RichText::new(format!("the {name} path")).small());
        }
    });
}

fn bounds_rows(ui: &mut egui::Ui, min: [f32; 3], max: [f32; 3]) {
    let finite = min.iter().chain(&max).all(|v| v.is_finite());
    if !finite || (0..3).any(|i| min[i] > max[i]) {
        grid::row(ui, "Bounds", "empty");
        return;
    }
    grid::row(ui, "Bounds min", format!("{} m", point(min)));
    grid::row(ui, "Bounds max", format!("{} m", point(max)));
    let size: Vec<String> = (0..3).map(|i| length(max[i] - min[i])).collect();
    grid::row(ui, "Size", format!("{} m", size.join(" × ")));
}
