//! Keyboard shortcuts, in one table: the keys the panel acts on ([`apply`]) and the lines of
//! the F1 help overlay ([`help`]), which also lists the camera's keys and mouse that the app
//! handles itself.

use egui::{Key, KeyboardShortcut, Modifiers};
use render_core::frame::{FrameSettings, Method};

use crate::{PanelTab, UiAction};

/// What a shortcut does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Command {
    NextMethod,
    PreviousMethod,
    LightView,
    CastersTint,
    CascadeTint,
    HeatMap,
    Measure,
    Shadows,
    CompareAll,
    Animate,
    Help,
    Tab(PanelTab),
    Action(UiAction),
}

const fn key(key: Key) -> KeyboardShortcut {
    KeyboardShortcut::new(Modifiers::NONE, key)
}

/// Every shortcut the panel handles but the tabs', with its line in the help. A shortcut with
/// Shift comes before the same key without, which would also match it.
const SHORTCUTS: [(KeyboardShortcut, Command, &str); 16] = [
    (
        KeyboardShortcut::new(Modifiers::SHIFT, Key::M),
        Command::PreviousMethod,
        "previous method",
    ),
    (key(Key::M), Command::NextMethod, "next method"),
    (key(Key::L), Command::LightView, "light view in the corner"),
    (key(Key::C), Command::CastersTint, "tint casters by outcome"),
    (key(Key::V), Command::CascadeTint, "tint by cascade"),
    (
        key(Key::H),
        Command::HeatMap,
        "error heat map (measures the error)",
    ),
    (key(Key::O), Command::Measure, "measure error and oracle"),
    (key(Key::B), Command::Shadows, "shadows on / off"),
    (key(Key::K), Command::CompareAll, "compare all methods"),
    (key(Key::P), Command::Animate, "animate dynamic objects"),
    (
        key(Key::F),
        Command::Action(UiAction::FrameScene),
        "frame the scene",
    ),
    (
        key(Key::X),
        Command::Action(UiAction::ToggleObserver),
        "observer camera: freeze the view, fly outside it",
    ),
    (
        key(Key::F12),
        Command::Action(UiAction::Screenshot),
        "screenshot",
    ),
    (
        KeyboardShortcut::new(Modifiers::COMMAND, Key::O),
        Command::Action(UiAction::OpenFile),
        "open a glTF file",
    ),
    (
        KeyboardShortcut::new(Modifiers::COMMAND, Key::R),
        Command::Action(UiAction::ReloadScene),
        "reload the scene",
    ),
    (key(Key::F1), Command::Help, "this help"),
];

/// The panel's tabs on F2 to F7, in the order of [`PanelTab::ALL`].
const TAB_KEYS: [Key; 6] = [Key::F2, Key::F3, Key::F4, Key::F5, Key::F6, Key::F7];

/// The keys and mouse the app's camera handles, for the help.
const CAMERA: [(&str, &str); 7] = [
    ("W A S D", "fly forward, left, back, right"),
    ("Q / E", "down / up"),
    ("Shift", "move faster"),
    ("right drag", "look around"),
    ("middle or Alt + left drag", "orbit the target"),
    ("wheel", "dolly towards the target"),
    ("left click", "select the object under the cursor"),
];

/// What the shortcuts pressed this frame change: settings are edited in place, the rest
/// returned.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Pressed {
    pub actions: Vec<UiAction>,
    pub tab: Option<PanelTab>,
    pub toggle_help: bool,
}

/// Consumes this frame's shortcut key presses, unless a text field has the keyboard.
pub fn apply(ctx: &egui::Context, settings: &mut FrameSettings) -> Pressed {
    let mut pressed = Pressed::default();
    if ctx.text_edit_focused() {
        return pressed;
    }
    let mut commands = Vec::new();
    ctx.input_mut(|input| {
        let tabs = TAB_KEYS
            .into_iter()
            .zip(PanelTab::ALL)
            .map(|(k, tab)| (key(k), Command::Tab(tab)));
        let all = SHORTCUTS.iter().map(|(s, c, _)| (*s, *c)).chain(tabs);
        for (shortcut, command) in all {
            let times = input.count_and_consume_key(shortcut.modifiers, shortcut.logical_key);
            commands.extend(std::iter::repeat_n(command, times));
        }
    });
    for command in commands {
        run(command, settings, &mut pressed);
    }
    pressed
}

fn run(command: Command, settings: &mut FrameSettings, pressed: &mut Pressed) {
    let step = |by: usize| {
        let all = Method::ALL;
        let at = all.iter().position(|m| *m == settings.method).unwrap_or(0);
        all[(at + by) % all.len()]
    };
    match command {
        Command::NextMethod => settings.method = step(1),
        Command::PreviousMethod => settings.method = step(Method::ALL.len() - 1),
        Command::LightView => settings.overlays.light_view ^= true,
        Command::CastersTint => settings.overlays.casters ^= true,
        Command::CascadeTint => settings.overlays.cascades ^= true,
        Command::HeatMap => {
            settings.overlays.error ^= true;
            settings.measure |= settings.overlays.error;
        }
        Command::Measure => settings.measure ^= true,
        Command::Shadows => settings.shadow.shadows_enabled ^= true,
        Command::CompareAll => settings.compare_all ^= true,
        Command::Animate => settings.animate ^= true,
        Command::Help => pressed.toggle_help ^= true,
        Command::Tab(tab) => pressed.tab = Some(tab),
        Command::Action(action) => pressed.actions.push(action),
    }
}

/// The help overlay's lines: keys, then what they do.
pub fn help() -> impl Iterator<Item = (String, &'static str)> {
    SHORTCUTS
        .iter()
        .map(|(shortcut, _, what)| (key_name(*shortcut), *what))
        .chain([(
            "F2 … F7".to_owned(),
            "panel tabs: Scene, Shadows, Compare, Counts, Timings, Light",
        )])
        .chain(
            CAMERA
                .iter()
                .map(|(keys, what)| ((*keys).to_owned(), *what)),
        )
}

fn key_name(shortcut: KeyboardShortcut) -> String {
    let mut name = String::new();
    if shortcut.modifiers.command {
        name.push_str("Ctrl + ");
    }
    if shortcut.modifiers.shift {
        name.push_str("Shift + ");
    }
    name.push_str(shortcut.logical_key.name());
    name
}

/// The help window, centred over `view` while `open`; its close button clears `open`.
pub fn show_help(ctx: &egui::Context, view: egui::Rect, open: &mut bool) {
    egui::Window::new("Keyboard shortcuts (F1)")
        .open(open)
        .order(egui::Order::Foreground)
        .collapsible(false)
        .resizable(false)
        .pivot(egui::Align2::CENTER_CENTER)
        .default_pos(view.center())
        .constrain_to(view)
        .show(ctx, |ui| {
            egui::Grid::new("shortcut_help")
                .num_columns(2)
                .spacing(crate::theme::GRID_SPACING)
                .striped(true)
                .show(ui, |ui| {
                    for (keys, what) in help() {
                        ui.label(egui::RichText::new(keys).monospace().strong());
                        ui.label(what);
                        ui.end_row();
                    }
                });
        });
}
