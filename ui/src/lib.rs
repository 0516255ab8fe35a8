//! egui panels and plots of shadowlab: plain data in (scene facts, frame reports), settings and
//! requested actions out. No GPU objects and no windowing here; the `app` crate owns those.
//!
//! The app calls [`theme::apply`] once, then each frame [`SidePanel::record`] with the newest
//! report, [`SidePanel::show`] (the keyboard shortcuts and the panel; [`SidePanel::ui`] draws
//! the panel into the caller's) and [`SidePanel::show_over_view`] (the overlays' legend and the
//! F1 help over the 3D view).

mod format;
pub mod history;
pub mod legend;
pub mod shortcuts;
mod side_panel;
pub mod theme;

pub use history::TimingHistory;
pub use side_panel::{PanelTab, SidePanel};

use render_core::frame::FrameReport;
use render_core::scene::SceneFacts;

/// The object the user clicked in the 3D view, and what happened to it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Selection {
    /// The glTF node name (with a chunk suffix for split objects).
    pub name: String,
    pub casts_shadow: bool,
    pub receives_shadow: bool,
    /// Some pixel of the last frame shows it.
    pub visible: bool,
    /// `rendered`, or the stage that culled it, as in the stats JSON.
    pub shadow_map: String,
    /// In the oracle set when the click happened (only when measuring).
    pub oracle: Option<bool>,
    /// With shadow volumes, where its volume was drawn when the click happened: each
    /// interval's start and end, metres along the light from the caster (empty: culled).
    pub volume_intervals: Option<Vec<[f32; 2]>>,
}

/// Where screenshots go and what they show.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScreenshotSettings {
    /// Folder the app writes screenshots into (created when missing).
    pub folder: String,
    /// Capture the whole window with this panel instead of the 3D view alone.
    pub include_panel: bool,
}

impl Default for ScreenshotSettings {
    fn default() -> Self {
        Self {
            folder: "screenshots-out".to_owned(),
            include_panel: false,
        }
    }
}

/// What the user asked for this frame; the app carries it out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UiAction {
    /// Show a file dialog and load the chosen glTF.
    OpenFile,
    /// Write a screenshot as [`ScreenshotSettings`] say.
    Screenshot,
    /// Move the camera so the whole scene is in view.
    FrameScene,
    /// Load the current scene again from its source.
    ReloadScene,
    /// Load the current scene again, its coordinates read in this unit.
    SetUnits(render_core::scene::Units),
    /// Method, shadow parameters, overlays, sun, camera and screenshot options back to their
    /// defaults.
    ResetSettings,
    /// Freeze the view and fly an observer camera outside it, or go back to the view.
    ToggleObserver,
    /// Add a spot light at the camera, shining where it looks.
    AddSpotLight,
    /// Remove the scene's light of this index.
    RemoveLight(usize),
    /// Move the scene's light of this index to this position.
    MoveLight(usize, Position),
    /// Start recording the camera's path, or stop and save it.
    RecordPath,
    /// Play the last recorded path (else the scene's own), or stop playing.
    PlayPath,
}

/// A position in metres, kept as the floats' bits so that actions compare exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Position([u32; 3]);

impl Position {
    pub fn new(metres: [f32; 3]) -> Self {
        Self(metres.map(f32::to_bits))
    }

    pub fn metres(self) -> [f32; 3] {
        self.0.map(f32::from_bits)
    }
}

/// Read-only facts the panel shows this frame.
#[derive(Clone, Copy, Debug)]
pub struct PanelInput<'a> {
    pub scene: &'a SceneFacts,
    /// The scene's point and spot lights (the many-lights technique edits them).
    pub lights: &'a [render_core::scene::PunctualLight],
    /// The unit the scene's file was read in (built-in scenes are in metres).
    pub units: render_core::scene::Units,
    /// The newest frame report; `None` before the first frame.
    pub report: Option<&'a FrameReport>,
    /// The light's view (shadow-map depth) as a 256x256 egui texture.
    pub light_view: Option<egui::TextureId>,
    /// GPU adapter description.
    pub adapter: &'a str,
    pub has_gpu_timestamps: bool,
    /// File name of the last screenshot written.
    pub last_screenshot: Option<&'a str>,
    /// Latest error or info message, shown at the top of the panel.
    pub message: Option<&'a str>,
    pub fps: Option<f32>,
    /// The object clicked in the 3D view, if any.
    pub selection: Option<&'a Selection>,
    /// Every method's row for the current view, while "compare all" is on.
    pub compare: Option<&'a [render_core::frame::compare::CompareRow]>,
    /// The file the window remembers its scene, camera and settings in.
    pub settings_file: Option<&'a str>,
    /// Recording or playing a camera path.
    pub path: PathState<'a>,
}

/// Camera paths in the window: recording, playing, the last file saved.
#[derive(Clone, Copy, Debug, Default)]
pub struct PathState<'a> {
    /// Keys recorded so far, while recording.
    pub recording_keys: Option<usize>,
    /// The path playing, by name.
    pub playing: Option<&'a str>,
    /// The CSV the last recording was saved to.
    pub last_saved: Option<&'a str>,
}
