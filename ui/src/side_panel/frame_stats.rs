//! The newest frame: what the shadow pass could not do as asked (over the tabs), its counts
//! and culling stages (the Counts tab), its timings (the Timings tab, above the plot).

use render_core::frame::FrameReport;

use super::grid;
use crate::format::{millis, thousands};
use crate::history::TimingSample;
use crate::{PanelInput, theme};

/// Shown where a count has not come back from the GPU yet.
const PENDING: &str = "…";

/// The Counts tab.
pub fn counts_ui(ui: &mut egui::Ui, input: &PanelInput<'_>) {
    match input.report {
        Some(report) => {
            counts(ui, report);
            stages(ui, report);
            views(ui, report);
        }
        None => {
            ui.label(egui::RichText::new("No frame rendered yet").color(theme::MUTED));
        }
    }
}

/// A shadow pass that could not run as asked, and what the device changes about the method:
/// shown first, in the warning colour, so a number below is not read as the method's own.
pub fn problems(ui: &mut egui::Ui, report: &FrameReport) {
    if let Some(failure) = &report.shadow_failure {
        ui.label(
            egui::RichText::new(format!("Shadow pass failed: {failure}")).color(theme::WARNING),
        );
    }
    for note in &report.notes {
        ui.label(egui::RichText::new(format!("Fallback: {note}")).color(theme::WARNING));
    }
}

/// Two counts as "a / b", each grouped by thousands.
fn of_two(a: u32, b: u32) -> String {
    format!("{} / {}", thousands(a.into()), thousands(b.into()))
}

fn counts(ui: &mut egui::Ui, report: &FrameReport) {
    let c = &report.counts;
    grid::facts(ui, "frame_counts", |ui| {
        grid::row(
            ui,
            "Casters rendered",
            of_two(c.casters_rendered, c.casters_total),
        );
        if let Some(passes) = report.volume_passes {
            grid::row(
                ui,
                "Volumes z-pass / z-fail",
                of_two(passes.z_pass, passes.z_fail),
            );
            grid::row(
                ui,
                "Cull: by workgroups / whole",
                of_two(passes.big_casters, passes.whole_past_budget),
            );
            grid::row(
                ui,
                "Volume triangles: quads / caps",
                of_two(passes.quad_triangles, passes.cap_triangles),
            );
        }
        if let Some(fill) = report.volume_fill {
            grid::row(
                ui,
                "Volume fill (stencil writes)",
                format!(
                    "{} ({})",
                    thousands(fill.fragments),
                    thousands(fill.stencil_writes)
                ),
            );
        }
        if let Some(oracle) = c.casters_oracle {
            grid::row(ui, "Oracle casters", thousands(oracle.into()));
            let tightness = report
                .tightness()
                .map_or_else(|| PENDING.to_owned(), |t| format!("{t:.2}"));
            grid::row(ui, "Tightness (drawn / oracle)", tightness);
        }
        if let Some(e) = report.error {
            grid::row(
                ui,
                "Missing shadow px",
                thousands(e.missing_shadow_px.into()),
            );
            grid::row(ui, "Extra shadow px", thousands(e.extra_shadow_px.into()));
            grid::row(ui, "Receiver px compared", thousands(e.visible_px.into()));
        }
        if c.casters_oracle.is_some() {
            // Sun-facing receiver pixels whose shadow differs from a ray cast towards the
            // sun: from a worker thread once the view is still (not while animating).
            let exact = report.exact_error.map_or_else(
                || PENDING.to_owned(),
                |e| {
                    format!(
                        "{} / {}",
                        thousands(e.missing_shadow_px.into()),
                        thousands(e.extra_shadow_px.into())
                    )
                },
            );
            grid::row(ui, "Vs exact: missing / extra", exact);
            // Of those, the pixels with no edge of the exact picture next to them: wrong
            // shadow that no sampling of an edge explains.
            if let Some(off) = report.exact_error.and_then(|e| e.off_edge_px) {
                grid::row(ui, "Vs exact: off edges", thousands(off.into()));
            }
        }
        if let Some(u) = report.undersampling {
            grid::row(
                ui,
                "Undersampling p50 / p95",
                format!("{:.2} / {:.2} octaves", u.median_octaves, u.p95_octaves),
            );
        }
        grid::row(ui, "Receivers visible", optional_count(c.receivers_visible));
        grid::row(
            ui,
            "Objects drawn (camera)",
            thousands(c.objects_drawn_camera.into()),
        );
        grid::row(ui, "Shadow triangles", thousands(c.triangles_shadow));
        grid::row(ui, "Camera triangles", thousands(c.triangles_camera));
    });
}

fn stages(ui: &mut egui::Ui, report: &FrameReport) {
    if report.stages.is_empty() {
        return;
    }
    ui.label(egui::RichText::new("Casters left after each stage").color(theme::MUTED));
    grid::facts(ui, "frame_stages", |ui| {
        for stage in &report.stages {
            grid::row(ui, &stage.name, thousands(stage.remaining.into()));
        }
    });
}

/// Per shadow view (a cascade each), when there are several: casters drawn, the oracle's and
/// the texel size.
fn views(ui: &mut egui::Ui, report: &FrameReport) {
    if report.views.len() < 2 {
        return;
    }
    ui.add_space(theme::SECTION_GAP);
    egui::Grid::new("frame_views")
        .num_columns(5)
        .striped(true)
        .spacing(theme::GRID_SPACING)
        .show(ui, |ui| {
            for heading in ["view", "casters", "oracle", "texel", "under p95"] {
                ui.label(egui::RichText::new(heading).color(theme::MUTED));
            }
            ui.end_row();
            for view in &report.views {
                ui.label(view.name.as_str());
                ui.label(thousands(view.casters_rendered.into()));
                ui.label(optional_count(view.casters_oracle));
                ui.label(format!("{} m", crate::format::length(view.texel_size_m[0])))
                    .on_hover_text(format!(
                        "depth bias {} m, PCF kernel {} m across: both follow the texel",
                        crate::format::length(view.depth_bias_m),
                        crate::format::length(view.pcf_m)
                    ));
                ui.label(
                    view.undersampling
                        .map_or_else(|| PENDING.to_owned(), |u| format!("{:.2}", u.p95_octaves)),
                );
                ui.end_row();
            }
        });
}

/// The Timings tab's numbers.
pub fn timings(ui: &mut egui::Ui, input: &PanelInput<'_>, newest: Option<&TimingSample>) {
    grid::facts(ui, "frame_timings", |ui| {
        grid::row(
            ui,
            "FPS",
            input
                .fps
                .map_or_else(|| PENDING.to_owned(), |f| format!("{f:.1}")),
        );
        grid::row(
            ui,
            "Frame",
            newest.map_or_else(|| PENDING.to_owned(), |s| millis(s.frame_ms)),
        );
        if let Some(report) = input.report {
            grid::row(ui, "CPU culling", millis(report.cpu.culling_ms));
            grid::row(ui, "CPU encode+submit", millis(report.cpu.encode_submit_ms));
            if input.has_gpu_timestamps {
                gpu_rows(ui, report);
            }
        }
    });
    if !input.has_gpu_timestamps {
        ui.label(
            egui::RichText::new("GPU timestamps not available on this adapter").color(theme::MUTED),
        );
    }
    grid::facts(ui, "frame_adapter", |ui| {
        ui.label(egui::RichText::new("Adapter").color(theme::MUTED));
        ui.add(egui::Label::new(input.adapter).wrap());
        ui.end_row();
    });
}

fn gpu_rows(ui: &mut egui::Ui, report: &FrameReport) {
    if report.gpu.is_empty() {
        grid::row(ui, "GPU", PENDING);
        return;
    }
    for pass in report.gpu_passes() {
        let label = match pass.depth {
            0 => format!("GPU {}", pass.label),
            depth => format!("{}{}", "  ".repeat(depth as usize + 1), pass.label),
        };
        grid::row(ui, &label, millis(pass.gpu_ms));
    }
    if let Some(total) = report.gpu_total_ms() {
        grid::row(ui, "GPU total", millis(total));
    }
}

fn optional_count(count: Option<u32>) -> String {
    count.map_or_else(|| PENDING.to_owned(), |n| thousands(n.into()))
}
