//! The legend of the overlays on the 3D view: a swatch and a line per colour, grouped by
//! overlay (`render_core::frame::legend`). The window shows it over the view's bottom-left
//! corner; headless shots and screenshots paint the same widget into the picture.

use render_core::frame::{LegendEntry, LegendGroup};

use crate::theme;

/// Side of a colour swatch, points.
const SWATCH: f32 = 11.0;

/// A linear colour as egui's (sRGB-encoded) colour, as the sRGB target shows it.
fn colour(rgb: [f32; 3]) -> egui::Color32 {
    egui::Rgba::from_rgb(rgb[0], rgb[1], rgb[2]).into()
}

fn swatch(ui: &mut egui::Ui, entry: &LegendEntry) {
    let (rect, _) = ui.allocate_exact_size(egui::Vec2::splat(SWATCH), egui::Sense::hover());
    let painter = ui.painter();
    let fill = colour(entry.rgb);
    if entry.striped {
        // Stripes over the map's grey, as the inset draws them.
        painter.rect_filled(rect, 0.0, egui::Color32::from_gray(90));
        let stroke = egui::Stroke::new(1.5, fill);
        for k in 0..4 {
            let t = k as f32 * SWATCH / 3.0;
            let a = rect.left_bottom() + egui::vec2(t, 0.0);
            let b = rect.left_bottom() + egui::vec2(0.0, -t);
            painter.line_segment([a, b], stroke);
            let c = rect.right_top() + egui::vec2(-t, 0.0);
            let d = rect.right_top() + egui::vec2(0.0, t);
            painter.line_segment([c, d], stroke);
        }
    } else {
        painter.rect_filled(rect, 0.0, fill);
    }
    painter.rect_stroke(
        rect,
        0.0,
        egui::Stroke::new(1.0, egui::Color32::from_gray(20)),
        egui::StrokeKind::Inside,
    );
}

/// One group: its title, then a line per colour.
fn group_ui(ui: &mut egui::Ui, group: &LegendGroup) {
    // Rows as high as their text, not as a button.
    ui.spacing_mut().interact_size.y = SWATCH + 3.0;
    ui.label(egui::RichText::new(group.title).strong().small());
    for entry in &group.entries {
        ui.horizontal(|ui| {
            ui.spacing_mut().item_spacing.x = 5.0;
            swatch(ui, entry);
            ui.label(egui::RichText::new(entry.label).small());
        });
    }
}

/// The groups one below the other, into `ui` (the panel's light view).
pub fn ui(ui: &mut egui::Ui, groups: &[LegendGroup]) {
    for (i, group) in groups.iter().enumerate() {
        if i > 0 {
            ui.add_space(theme::SECTION_GAP);
        }
        group_ui(ui, group);
    }
}

/// The groups side by side, so the legend stays low over the view, wrapping to a new row where
/// the view is narrow.
fn columns_ui(ui: &mut egui::Ui, groups: &[LegendGroup]) {
    ui.horizontal_wrapped(|ui| {
        for (i, group) in groups.iter().enumerate() {
            if i > 0 {
                ui.add_space(theme::LEGEND_MARGIN);
            }
            ui.vertical(|ui| group_ui(ui, group));
        }
    });
}

/// The legend over the bottom-left corner of `view` (the 3D view's rectangle), on a dark
/// translucent frame; nothing when `groups` is empty.
pub fn show(ctx: &egui::Context, view: egui::Rect, groups: &[LegendGroup]) {
    if groups.is_empty() {
        return;
    }
    egui::Area::new(egui::Id::unique("shadowlab_legend"))
        .order(egui::Order::Foreground)
        .interactable(false)
        .fade_in(false)
        .pivot(egui::Align2::LEFT_BOTTOM)
        .fixed_pos(view.left_bottom() + egui::vec2(theme::LEGEND_MARGIN, -theme::LEGEND_MARGIN))
        .constrain_to(view)
        .show(ctx, |ui| {
            egui::Frame::new()
                .fill(theme::LEGEND_FILL)
                .corner_radius(4.0)
                .inner_margin(6.0)
                .show(ui, |ui| {
                    ui.set_max_width(view.width() - 4.0 * theme::LEGEND_MARGIN);
                    ui.style_mut().visuals.override_text_color = Some(theme::LEGEND_TEXT);
                    ui.spacing_mut().item_spacing.y = 2.0;
                    columns_ui(ui, groups);
                });
        });
}
