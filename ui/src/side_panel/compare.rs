//! "Compare all": every method's casters, tightness, error and GPU times for the current view
//! in one table, while the selected method drives the picture.

use egui_plot::{HoverPosition, Plot, PlotPoints, Points};
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
    speed_against_error(ui, rows, selected);
}

/// Each method's shadow GPU time (its maps and its culling) against its error pixels, a point
/// each, the selected one larger; hovering names the row.
fn speed_against_error(ui: &mut egui::Ui, rows: &[CompareRow], selected: Method) {
    let points: Vec<(&CompareRow, [f64; 2])> = rows
        .iter()
        .filter_map(|r| Some((r, speed_and_error(r)?)))
        .collect();
    if points.is_empty() {
        return;
    }
    ui.add_space(theme::SECTION_GAP);
    ui.label(
        egui::RichText::new("speed against error: shadow + cull ms (x), error px (y)")
            .small()
            .color(theme::MUTED),
    );
    Plot::new("compare_speed_error")
        .height(theme::PLOT_HEIGHT)
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
        .include_x(0.0)
        .include_y(0.0)
        // A margin past the furthest point, so none sits on the frame.
        .include_x(points.iter().map(|(_, p)| p[0]).fold(0.0, f64::max) * 1.1)
        .include_y(points.iter().map(|(_, p)| p[1]).fold(1.0, f64::max) * 1.1)
        .label_formatter(|hover| match hover {
            HoverPosition::NearDataPoint {
                plot_name,
                position,
                ..
            } if !plot_name.is_empty() => Some(format!(
                "{plot_name}\n{:.2} ms, {:.0} px",
                position.x, position.y
            )),
            _ => None,
        })
        .show(ui, |plot| {
            for (i, (row, at)) in points.iter().enumerate() {
                let radius = if row.method == selected { 6.0 } else { 3.5 };
                plot.points(
                    Points::new(row.method.name(), PlotPoints::from(vec![*at]))
                        .radius(radius)
                        .color(theme::pass_line(i)),
                );
            }
        });
}

/// A row's point: shadow and culling GPU ms, error pixels; none without both.
pub fn speed_and_error(row: &CompareRow) -> Option<[f64; 2]> {
    let ms = row.shadow_ms? + row.culling_ms.unwrap_or(0.0);
    Some([ms, f64::from(row.error_px?)])
}
