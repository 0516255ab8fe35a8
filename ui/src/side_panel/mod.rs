//! The side panel: a message line, then tabs (`egui_tiles`, so a tab can also be dragged
//! beside another): Scene (facts, selection, sun, screenshots), Shadows (method and settings),
//! Compare (every method's row), Counts (casters, error, stages), Timings (CPU and GPU times
//! and their plot) and Light (the light's view and its legend). A failed shadow pass is named
//! over the tabs. Each tab fits a 720-pixel-high window and scrolls below that.

mod cascades;
mod compare;
mod frame_stats;
mod grid;
mod light_view;
mod lights;
mod message;
mod scene;
mod screenshot;
mod selection;
mod shadows;
mod sun;
mod timings_plot;
mod virtual_pages;

#[cfg(test)]
mod tests;

use render_core::frame::{FrameReport, FrameSettings};

use crate::history::TimingHistory;
use crate::{PanelInput, ScreenshotSettings, UiAction, legend, shortcuts, theme};

/// A tab of the side panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PanelTab {
    Scene,
    Shadows,
    Compare,
    Counts,
    Timings,
    Light,
}

impl PanelTab {
    pub const ALL: [Self; 6] = [
        Self::Scene,
        Self::Shadows,
        Self::Compare,
        Self::Counts,
        Self::Timings,
        Self::Light,
    ];

    pub fn title(self) -> &'static str {
        match self {
            Self::Scene => "Scene",
            Self::Shadows => "Shadows",
            Self::Compare => "Compare",
            Self::Counts => "Counts",
            Self::Timings => "Timings",
            Self::Light => "Light",
        }
    }
}

/// The lab's control and statistics panel. Long-lived: it keeps the timing history, the sun
/// angles the user set, the tabs' layout and whether the help is open.
#[derive(Debug)]
pub struct SidePanel {
    history: TimingHistory,
    sun: sun::SunEditor,
    tabs: egui_tiles::Tree<PanelTab>,
    help_open: bool,
}

impl Default for SidePanel {
    fn default() -> Self {
        Self {
            history: TimingHistory::default(),
            sun: sun::SunEditor::default(),
            tabs: egui_tiles::Tree::new_tabs(
                egui::Id::unique("shadowlab_panel_tabs"),
                PanelTab::ALL.to_vec(),
            ),
            help_open: false,
        }
    }
}

impl SidePanel {
    pub fn new() -> Self {
        Self::default()
    }

    /// Call once per frame with the newest report (also feeds the history plot).
    /// `time_s` is any monotonic clock in seconds; `frame_ms` the wall time of the frame.
    pub fn record(&mut self, time_s: f64, report: &FrameReport, frame_ms: f64) {
        self.history.push(time_s, frame_ms, &report.gpu);
    }

    /// The recorded frame and pass times.
    pub fn history(&self) -> &TimingHistory {
        &self.history
    }

    /// Brings `tab` to the front.
    pub fn open_tab(&mut self, tab: PanelTab) {
        self.tabs
            .make_active(|_, tile| matches!(tile, egui_tiles::Tile::Pane(t) if *t == tab));
    }

    /// The tabs shown now (one, unless the user dragged a tab beside another).
    pub fn shown_tabs(&self) -> Vec<PanelTab> {
        let active = self.tabs.active_tiles();
        PanelTab::ALL
            .into_iter()
            .filter(|tab| {
                active.iter().any(|id| {
                    matches!(self.tabs.tiles.get(*id), Some(egui_tiles::Tile::Pane(t)) if t == tab)
                })
            })
            .collect()
    }

    /// Whether the keyboard help (F1) is open.
    pub fn help_open(&self) -> bool {
        self.help_open
    }

    /// Draws the message and the tabs into `ui` (the caller provides the panel), edits
    /// `settings` and `screenshot`, and returns what the user asked for this frame.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        settings: &mut FrameSettings,
        screenshot: &mut ScreenshotSettings,
        input: &PanelInput<'_>,
    ) -> Vec<UiAction> {
        let mut actions = Vec::new();
        if let Some(text) = input.message {
            message::ui(ui, text);
        }
        if let Some(report) = input.report {
            frame_stats::problems(ui, report);
        }
        ui.horizontal(|ui| {
            ui.label(egui::RichText::new(settings.method.name()).strong())
                .on_hover_text(settings.method.summary());
            ui.label(egui::RichText::new("M / Shift+M: method").color(theme::MUTED));
            if ui
                .small_button("Shortcuts (F1)")
                .on_hover_text("Every keyboard shortcut and mouse control")
                .clicked()
            {
                self.help_open ^= true;
            }
        });
        let mut panes = Panes {
            history: &self.history,
            sun: &mut self.sun,
            settings,
            screenshot,
            input,
            actions: &mut actions,
        };
        self.tabs.ui(&mut panes, ui);
        actions
    }

    /// Takes this frame's keyboard shortcuts, then shows the panel on the left of `root_ui`
    /// (resizable) and returns what the user asked for. The space left in `root_ui` afterwards
    /// is the 3D view's; pass it to [`SidePanel::show_over_view`].
    pub fn show(
        &mut self,
        root_ui: &mut egui::Ui,
        settings: &mut FrameSettings,
        screenshot: &mut ScreenshotSettings,
        input: &PanelInput<'_>,
    ) -> Vec<UiAction> {
        let pressed = shortcuts::apply(root_ui.ctx(), settings);
        if let Some(tab) = pressed.tab {
            self.open_tab(tab);
        }
        self.help_open ^= pressed.toggle_help;
        let mut actions = pressed.actions;
        let panel = egui::Panel::left("shadowlab_side_panel")
            .default_size(theme::SIDE_PANEL_WIDTH)
            .resizable(true)
            .show(root_ui, |ui| self.ui(ui, settings, screenshot, input));
        actions.extend(panel.inner);
        actions
    }

    /// Over the 3D view's rectangle `view`: the legend of the overlays `settings` turn on,
    /// and the keyboard help while it is open.
    pub fn show_over_view(
        &mut self,
        ctx: &egui::Context,
        view: egui::Rect,
        settings: &FrameSettings,
    ) {
        legend::show(ctx, view, &render_core::frame::legend(settings));
        if self.help_open {
            shortcuts::show_help(ctx, view, &mut self.help_open);
        }
    }
}

/// What the tabs draw from and edit this frame.
struct Panes<'a, 'i> {
    history: &'a TimingHistory,
    sun: &'a mut sun::SunEditor,
    settings: &'a mut FrameSettings,
    screenshot: &'a mut ScreenshotSettings,
    input: &'a PanelInput<'i>,
    actions: &'a mut Vec<UiAction>,
}

impl Panes<'_, '_> {
    fn tab_ui(&mut self, ui: &mut egui::Ui, tab: PanelTab) {
        let input = self.input;
        match tab {
            PanelTab::Scene => {
                scene::ui(
                    ui,
                    (input.scene, input.units),
                    &mut self.settings.animate,
                    self.actions,
                );
                scene::path_ui(ui, &input.path, self.actions);
                if let Some(selected) = input.selection {
                    heading(ui, "Selected object");
                    selection::ui(ui, selected);
                }
                heading(ui, "Sun");
                point_light_ui(ui, input.scene.point_light, self.settings);
                self.sun.ui(ui, &mut self.settings.sun);
                heading(ui, "Screenshot");
                screenshot::ui(ui, self.screenshot, input.last_screenshot, self.actions);
            }
            PanelTab::Shadows => {
                shadows::ui(ui, self.settings);
                heading(ui, "Setup");
                cascades::ui(ui, self.settings, input.report);
                if self.settings.setup == render_core::frame::ShadowSetup::Lights {
                    heading(ui, "Lights");
                    lights::edit_ui(ui, input.lights, self.actions);
                }
                ui.add_space(theme::SECTION_GAP);
                shadows::remembered_ui(ui, input.settings_file, self.actions);
            }
            PanelTab::Compare => compare::ui(
                ui,
                &mut self.settings.compare_all,
                self.settings.method,
                input.compare,
            ),
            PanelTab::Counts => frame_stats::counts_ui(ui, input),
            PanelTab::Timings => {
                frame_stats::timings(ui, input, self.history.newest());
                ui.add_space(theme::SECTION_GAP);
                timings_plot::ui(ui, self.history);
            }
            PanelTab::Light => light_view::ui(ui, input, self.settings),
        }
    }
}

impl egui_tiles::Behavior<PanelTab> for Panes<'_, '_> {
    fn tab_title_for_pane(&mut self, tab: &PanelTab) -> egui::WidgetText {
        tab.title().into()
    }

    fn pane_ui(
        &mut self,
        ui: &mut egui::Ui,
        _tile: egui_tiles::TileId,
        tab: &mut PanelTab,
    ) -> egui_tiles::UiResponse {
        egui::ScrollArea::vertical()
            .id_salt(tab.title())
            .auto_shrink([false, false])
            .show(ui, |ui| {
                egui::Frame::new()
                    .inner_margin(theme::TAB_MARGIN)
                    .show(ui, |ui| self.tab_ui(ui, *tab));
            });
        egui_tiles::UiResponse::None
    }

    fn tab_title_spacing(&self, _visuals: &egui::Visuals) -> f32 {
        theme::TAB_TITLE_SPACING
    }

    fn simplification_options(&self) -> egui_tiles::SimplificationOptions {
        egui_tiles::SimplificationOptions {
            all_panes_must_have_tabs: true,
            ..Default::default()
        }
    }
}

/// A part's title within a tab.
fn heading(ui: &mut egui::Ui, title: &str) {
    ui.add_space(theme::SECTION_GAP);
    ui.label(egui::RichText::new(title).strong());
    ui.separator();
}

/// Whether the scene's first point or spot light casts the shadows and lights the view
/// instead of the sun (shadow volumes and virtual maps: shadow maps report that they cannot).
fn point_light_ui(
    ui: &mut egui::Ui,
    point: Option<render_core::scene::PointShadow>,
    settings: &mut render_core::frame::FrameSettings,
) {
    let Some(point) = point else {
        return;
    };
    let mut on = settings.point_light.is_some();
    let p = point.position;
    let chain = render_core::shadow_view::spot_chain(&point);
    let (label, kind, pages) = match point.cone {
        Some(_) if chain.is_some() => (
            "From the spot light",
            "spot light",
            "a chain of pages along its cone",
        ),
        Some(_) => (
            "From the spot light",
            "spot light",
            "a cube of pages, the cone being wider than a face",
        ),
        None => ("From the point light", "point light", "a cube of pages"),
    };
    let help = format!(
        "Cast the shadows from the scene's {kind} at {:.1}, {:.1}, {:.1} m ({:.0} cd) instead \
         of the sun: shadow volumes and virtual maps ({pages})",
        p.x, p.y, p.z, point.intensity_cd
    );
    if ui.checkbox(&mut on, label).on_hover_text(help).changed() {
        settings.point_light = on.then_some(point);
    }
}
