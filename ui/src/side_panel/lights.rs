//! The many-lights technique's rows of the Shadows tab: how its maps are rendered, how many
//! lights shine, and what the last frame did.

use render_core::frame::FrameReport;
use render_core::shadow_view::{LayeredPath, LayeredSettings};

use super::grid;

const PATH_HELP: &str = "How the lights' shadow maps are rendered (Rákos, GPU Pro 4): \
     traditional, a pass per map; multiview, a pass per group of maps, a layer each; atlas, \
     one instanced draw per mesh for every map, each in its tile of an atlas";
const LIGHTS_HELP: &str = "Only the scene's first this many lights shine and cast shadows \
     (0: all). A spot light has one map, a point light six";

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
