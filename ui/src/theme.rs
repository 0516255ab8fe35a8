//! Colours, sizes and spacing of every panel, in one place.

use egui::{Color32, Vec2};

/// Messages the user must read: load errors, failed screenshots.
pub const WARNING: Color32 = Color32::from_rgb(255, 176, 64);
/// Captions and secondary facts.
pub const MUTED: Color32 = Color32::from_gray(150);
/// The frame-time line of the timings plot.
pub const FRAME_LINE: Color32 = Color32::from_rgb(230, 230, 230);
/// GPU pass lines of the timings plot, in order of first appearance.
pub const PASS_LINES: [Color32; 6] = [
    Color32::from_rgb(102, 178, 255),
    Color32::from_rgb(255, 128, 102),
    Color32::from_rgb(128, 214, 120),
    Color32::from_rgb(214, 153, 255),
    Color32::from_rgb(255, 214, 90),
    Color32::from_rgb(90, 214, 214),
];

/// Default outer width of the side panel, points.
pub const SIDE_PANEL_WIDTH: f32 = 370.0;
/// Largest side of the light-view inset, points.
pub const LIGHT_VIEW_SIZE: f32 = 200.0;
/// Height of the cascades' texel plot, points.
pub const CASCADE_PLOT_HEIGHT: f32 = 110.0;
/// Height of the timings plot, points.
pub const PLOT_HEIGHT: f32 = 140.0;
/// Gap between the columns and rows of the fact grids.
pub const GRID_SPACING: Vec2 = Vec2::new(12.0, 4.0);
/// Space either side of a tab's title, points.
pub const TAB_TITLE_SPACING: f32 = 5.0;
/// Space between a tab's edge and its contents.
pub const TAB_MARGIN: egui::Margin = egui::Margin::symmetric(4, 6);
/// Gap between sections.
pub const SECTION_GAP: f32 = 6.0;
/// Gap between the legend and the view's corner, points.
pub const LEGEND_MARGIN: f32 = 8.0;
/// The legend's background over the 3D view, and its text.
pub const LEGEND_FILL: Color32 = Color32::from_rgba_premultiplied(10, 10, 14, 215);
pub const LEGEND_TEXT: Color32 = Color32::from_gray(235);
/// Width of sliders in the settings grids.
pub const SLIDER_WIDTH: f32 = 90.0;

/// Colour of the `index`-th GPU pass line.
pub fn pass_line(index: usize) -> Color32 {
    PASS_LINES[index % PASS_LINES.len()]
}

/// Applies shadowlab's spacing to every theme of `ctx`. Call once after creating the context.
pub fn apply(ctx: &egui::Context) {
    ctx.all_styles_mut(|style| {
        style.spacing.item_spacing = Vec2::new(8.0, 5.0);
        style.spacing.slider_width = SLIDER_WIDTH;
        style.spacing.combo_width = 90.0;
        style.spacing.text_edit_width = 170.0;
        style.visuals.warn_fg_color = WARNING;
    });
}
