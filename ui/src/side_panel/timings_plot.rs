//! Frame time and GPU pass times over the last seconds.

use egui_plot::{Corner, Legend, Line, Plot, PlotPoints};

use crate::history::TimingHistory;
use crate::theme;

pub fn ui(ui: &mut egui::Ui, history: &TimingHistory) {
    if history.is_empty() {
        ui.label(egui::RichText::new("No frames recorded yet").color(theme::MUTED));
        return;
    }
    ui.label(
        egui::RichText::new(format!("ms over the last {:.0} s", TimingHistory::WINDOW_S))
            .small()
            .color(theme::MUTED),
    );
    let frame = history.frame_series();
    let passes = history.pass_series();
    Plot::new("timings_plot")
        .height(theme::PLOT_HEIGHT)
        .legend(
            Legend::default()
                .position(Corner::LeftTop)
                .text_style(egui::TextStyle::Small)
                .follow_insertion_order(true),
        )
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
        .allow_double_click_reset(false)
        .include_x(-TimingHistory::WINDOW_S)
        .include_x(0.0)
        .include_y(0.0)
        .show(ui, |plot| {
            plot.line(Line::new("frame", PlotPoints::from(frame)).color(theme::FRAME_LINE));
            for (i, (label, points)) in passes.into_iter().enumerate() {
                plot.line(Line::new(label, PlotPoints::from(points)).color(theme::pass_line(i)));
            }
        });
}
