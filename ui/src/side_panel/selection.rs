//! The object the user clicked: what it is and why it was drawn into the shadow map or culled.

use super::grid;
use crate::Selection;

fn yes_no(value: bool) -> &'static str {
    if value { "yes" } else { "no" }
}

/// The selection's facts; a shadow volume's intervals run along the light from the caster.
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
        if let Some(intervals) = &selection.volume_intervals {
            grid::row(ui, "Volume intervals", intervals_text(intervals));
        }
    });
}

/// A volume's intervals as "0-12.5 m, 30.1-31.0 m", or that it was culled. Along the light
/// from the caster.
pub(crate) fn intervals_text(intervals: &[[f32; 2]]) -> String {
    if intervals.is_empty() {
        return "none (culled)".to_owned();
    }
    intervals
        .iter()
        .map(|[start, end]| format!("{start:.1}-{end:.1} m"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    #[test]
    fn intervals_read_as_metres_along_the_light() {
        assert_eq!(super::intervals_text(&[]), "none (culled)");
        assert_eq!(
            super::intervals_text(&[[0.0, 12.54], [30.06, 31.0]]),
            "0.0-12.5 m, 30.1-31.0 m"
        );
    }
}
