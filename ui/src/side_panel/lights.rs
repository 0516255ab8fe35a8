//! The many-lights technique's rows of the Shadows tab: how its maps are rendered, how many
//! lights shine, and what the last frame did.

use render_core::frame::FrameReport;
use render_core::scene::PunctualLight;
use render_core::shadow_view::{LayeredPath, LayeredSettings};

use super::grid;
use crate::UiAction;

const PATH_HELP: &str = "How the lights' shadow maps are rendered (Rákos, GPU Pro 4): \
     traditional, a pass per map; multiview, a pass per group of maps, a layer each; atlas, \
     one instanced draw per mesh for every map, each in its tile of an atlas";
const LIGHTS_HELP: &str = "Only the scene's first this many lights shine and cast shadows \
     (0: all). A spot light has one map, a point light six";

const SUN_HELP: &str = "The sun shines too, shadowed by cascades (set below) that the same \
     path renders with the lights' maps, as an engine draws its sun and its lamps";

/// The rows (inside the tab's grid).
pub fn rows(ui: &mut egui::Ui, layered: &mut LayeredSettings, report: Option<&FrameReport>) {
    grid::labelled(ui, "Maps by", PATH_HELP, |ui| {
        egui::ComboBox::from_id_salt("layered_path")
            .selected_text(layered.path.name())
            .show_ui(ui, |ui| {
                for path in LayeredPath::ALL {
                    ui.selectable_value(&mut layered.path, path, path.name());
                }
            })
            .response
    });
    grid::labelled(ui, "Lights", LIGHTS_HELP, |ui| {
        ui.add(egui::DragValue::new(&mut layered.lights).range(0..=1024))
    });
    grid::labelled(ui, "Sun", SUN_HELP, |ui| {
        ui.checkbox(&mut layered.sun, "by cascades")
    });
    let Some(facts) = report.and_then(|r| r.layered) else {
        return;
    };
    let drawn = if facts.path == layered.path {
        facts.path.name().to_owned()
    } else {
        format!("{} (fallback)", facts.path.name())
    };
    grid::row(
        ui,
        "Drawn",
        format!(
            "{} lights, {} maps: {} passes, {} draws by {drawn}",
            facts.lights, facts.maps, facts.passes, facts.draws
        ),
    );
    if facts.multiview_group > 0 {
        grid::row(
            ui,
            "Multiview",
            format!("up to {} maps a pass here", facts.multiview_group),
        );
    }
}

const EDIT_HELP: &str = "The light whose position the fields below edit";
const POSITION_HELP: &str = "Where the light is, metres (x, y up, z)";

/// Choosing one of the scene's lights, moving it, removing it, and adding a spot light at the
/// camera: the scene changes at once, and the next frame renders its maps.
pub fn edit_ui(ui: &mut egui::Ui, lights: &[PunctualLight], actions: &mut Vec<UiAction>) {
    let id = ui.scope_id().with("edited_light");
    let mut chosen: usize = ui.data(|d| d.get_temp(id)).unwrap_or(0);
    chosen = chosen.min(lights.len().saturating_sub(1));
    if let Some(light) = lights.get(chosen) {
        grid::facts(ui, "light_edit", |ui| {
            grid::labelled(ui, "Edit", EDIT_HELP, |ui| {
                egui::ComboBox::from_id_salt("edited_light")
                    .selected_text(light.name.as_str())
                    .show_ui(ui, |ui| {
                        for (i, l) in lights.iter().enumerate() {
                            ui.selectable_value(&mut chosen, i, l.name.as_str());
                        }
                    })
                    .response
            });
            let mut position = light.position.to_array();
            let mut moved = false;
            grid::labelled(ui, "Position", POSITION_HELP, |ui| {
                ui.horizontal(|ui| {
                    for (axis, value) in ["x ", "y ", "z "].iter().zip(&mut position) {
                        let drag = egui::DragValue::new(value).speed(0.1).prefix(*axis);
                        moved |= ui.add(drag).changed();
                    }
                })
                .response
            });
            if moved {
                actions.push(UiAction::MoveLight(chosen, crate::Position::new(position)));
            }
        });
    } else {
        ui.label("The scene has no point or spot lights.");
    }
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Add spot at camera")
            .on_hover_text("A spot light where the camera is, shining where it looks")
            .clicked()
        {
            actions.push(UiAction::AddSpotLight);
        }
        if !lights.is_empty()
            && ui
                .button("Remove")
                .on_hover_text("Remove the light chosen above")
                .clicked()
        {
            actions.push(UiAction::RemoveLight(chosen));
        }
    });
    ui.data_mut(|d| d.insert_temp(id, chosen));
}
