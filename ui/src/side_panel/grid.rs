//! Two-column fact grids: a name on the left, its value on the right.

use crate::theme;

/// A two-column grid with the panel's spacing.
pub fn facts<R>(ui: &mut egui::Ui, id_salt: &str, add_rows: impl FnOnce(&mut egui::Ui) -> R) -> R {
    egui::Grid::new(id_salt)
        .num_columns(2)
        .spacing(theme::GRID_SPACING)
        .show(ui, add_rows)
        .inner
}

/// One row: `name` in the muted colour, `value` as plain text.
pub fn row(ui: &mut egui::Ui, name: &str, value: impl Into<egui::WidgetText>) {
    ui.label(egui::RichText::new(name).color(theme::MUTED));
    ui.label(value);
    ui.end_row();
}

/// A row with a widget on the right that `name` labels (for screen readers and tests), and a
/// hover text on both.
pub fn labelled(
    ui: &mut egui::Ui,
    name: &str,
    hover: &str,
    add_widget: impl FnOnce(&mut egui::Ui) -> egui::Response,
) -> egui::Response {
    let label = ui.label(name).on_hover_text(hover);
    let response = add_widget(ui).labelled_by(label.id).on_hover_text(hover);
    ui.end_row();
    response
}
