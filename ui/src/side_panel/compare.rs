//! "Compare all": every method's casters, tightness, error and GPU times for the current view
//! in one table, while the selected method drives the picture.

use render_core::frame::Method;
use render_core::frame::compare::CompareRow;

use crate::format::{millis, thousands};
use crate::theme;

const COMPARE_HELP: &str = "Render the current view with every method in the background (one \
    measured frame per displayed frame, each method until it settles) and list them side by \
    side. Halves the frame rate while on.";

pub fn ui(
    ui: &mut egui::Ui,
    compare_all: &mut bool,
    selected: Method,
    rows: Option<&[CompareRow]>,
) {
    ui.checkbox(compare_all, "Compare all methods")
        .on_hover_text(COMPARE_HELP);
    let Some(rows) = rows.filter(|r| *compare_all && !r.is_empty()) else {
        return;
    };
    egui::Grid::new("compare_all")
        .num_columns(6)
        .striped(true)
        .spacing(theme::GRID_SPACING)
        .show(ui, |ui| {
            for heading in [
                "method",
                "casters",
                "× oracle",
                // Two lines, so the columns are as narrow as their numbers.
                "error\npx",
                "shadow\nms",
                "cull\nms",
            ] {
                ui.label(egui::RichText::new(heading).color(theme::MUTED));
            }
            ui.end_row();
            for row in rows {
                let mut name = egui::RichText::new(row.method.name());
                if row.method == selected {
                    name = name.strong();
                }
                if row.stale {
                    name = name.color(theme::MUTED);
                }
                ui.label(name);
                ui.label(thousands(u64::from(row.casters_rendered)));
                ui.label(row.tightness().map_or("–".into(), |t| format!("{t:.2}")));
                let error = row.error_px.map_or("–".into(), |e| thousands(u64::from(e)));
                if row.error_px.is_some_and(|e| e > 0) {
                    ui.colored_label(theme::WARNING, error);
                } else {
                    ui.label(error);
                }
                // The unit is in the heading, so the columns stay narrow.
                for ms in [row.shadow_ms, row.culling_ms] {
                    ui.label(ms.map_or("–".into(), |ms| {
                        millis(ms).trim_end_matches(" ms").to_owned()
                    }));
                }
                ui.end_row();
            }
        });
    ui.label(
        egui::RichText::new("grey rows: computed for an earlier view")
            .small()
            .color(theme::MUTED),
    );
}
