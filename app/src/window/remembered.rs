//! What the window remembers between runs: the last scene (and its unit), the camera, the sun,
//! the shadow settings, overlays and screenshot options. A JSON file in the user's config
//! folder (`directories`: `~/.config/shadowlab/settings.json` on Linux), or in
//! `$SHADOWLAB_CONFIG_DIR` when that is set (the tests use it). Written when the window closes;
//! read when it opens. A file that cannot be read is kept beside as `settings.json.broken` and
//! named in the panel, never silently replaced.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use render_core::frame::FrameSettings;
use render_core::geom::Camera;
use render_core::scene::{Sun, Units};
use serde::{Deserialize, Serialize};

use crate::cli::{DEFAULT_SCENE, OpenArgs};
use crate::scene_source::LoadOptions;

/// Overrides the config folder (`settings.json` goes inside).
pub const CONFIG_DIR_VAR: &str = "SHADOWLAB_CONFIG_DIR";
const FILE_NAME: &str = "settings.json";

/// The remembered state. Fields missing from an older file take their defaults.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Remembered {
    /// `builtin:NAME` or a glTF path, as it was opened.
    pub scene: Option<String>,
    pub units: Units,
    /// The camera in the scene above, with its fly speed.
    pub camera: Option<Camera>,
    pub fly_speed_m_per_s: Option<f32>,
    pub sun: Option<Sun>,
    /// Method, shadow parameters, overlays, measuring and animation.
    pub frame: FrameSettings,
    pub screenshot_folder: Option<String>,
    pub include_panel: bool,
}

/// Where the settings live on this machine, if the system names a config folder.
pub fn settings_path() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os(CONFIG_DIR_VAR).filter(|d| !d.is_empty()) {
        return Some(PathBuf::from(dir).join(FILE_NAME));
    }
    directories::ProjectDirs::from("", "", "shadowlab").map(|d| d.config_dir().join(FILE_NAME))
}

impl Remembered {
    /// Reads `path`: `Ok(None)` when there is no file yet. A file that does not parse is moved
    /// to `*.broken` (so the next write cannot lose it) and the error names both.
    pub fn read(path: &Path) -> anyhow::Result<Option<Self>> {
        let text = match std::fs::read_to_string(path) {
            Ok(text) => text,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
        };
        match serde_json::from_str(&text) {
            Ok(remembered) => Ok(Some(remembered)),
            Err(e) => {
                let kept = path.with_extension("json.broken");
                let moved = std::fs::rename(path, &kept);
                let kept = match moved {
                    Ok(()) => format!("kept as {}", kept.display()),
                    Err(m) => format!("could not be moved aside: {m}"),
                };
                anyhow::bail!(
                    "{} is not valid settings ({e}); it was {kept}, and the defaults are used",
                    path.display()
                )
            }
        }
    }

    /// Writes `path`, creating its folder.
    pub fn write(&self, path: &Path) -> anyhow::Result<()> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("creating the settings folder {}", dir.display()))?;
        }
        let text = serde_json::to_string_pretty(self)?;
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
    }
}

impl super::Running {
    /// Writes what the window shows now to the settings file (when the window closes).
    pub(super) fn remember(&self) {
        let Some(path) = &self.settings_file else {
            return;
        };
        let remembered = Remembered {
            scene: Some(self.scene_spec.clone()),
            units: self.load_options.units,
            camera: Some(self.frozen_view.unwrap_or(self.controller.camera)),
            fly_speed_m_per_s: Some(self.controller.fly_speed_m_per_s),
            sun: Some(self.settings.sun),
            frame: self.settings,
            screenshot_folder: Some(self.screenshot_settings.folder.clone()),
            include_panel: self.screenshot_settings.include_panel,
        };
        match remembered.write(path) {
            Ok(()) => log::info!("settings saved to {}", path.display()),
            Err(e) => log::error!("the settings were not saved: {e:#}"),
        }
    }

    /// The panel's "Reset settings": method, shadow parameters, overlays, sun, camera and
    /// screenshot options back to their defaults; the scene stays.
    pub(super) fn reset_settings(&mut self) {
        self.settings = FrameSettings {
            sun: self.scene.sun,
            ..FrameSettings::default()
        };
        self.screenshot_settings = ui::ScreenshotSettings::default();
        self.frame_scene();
        self.message = Some(match &self.settings_file {
            Some(path) => format!(
                "Settings reset to their defaults; {} is written when the window closes",
                path.display()
            ),
            None => "Settings reset to their defaults".to_owned(),
        });
    }
}

/// What the window opens with: the command line's choices over the remembered ones.
#[derive(Debug)]
pub struct Restored {
    pub spec: String,
    pub options: LoadOptions,
    /// The spec came from the file, not the command line: when it no longer loads, the window
    /// opens the default scene instead of failing.
    pub spec_remembered: bool,
    /// The remembered camera and sun, when the scene is the remembered one.
    pub camera: Option<(Camera, Option<f32>)>,
    pub sun: Option<Sun>,
    /// Frame settings before the command line's flags apply.
    pub frame: FrameSettings,
    pub screenshot: Option<(String, bool)>,
    /// A file that could not be read, for the panel.
    pub problem: Option<String>,
}

/// Combines the remembered state at `path` with the command line: a scene on the command
/// line wins (with its `--units`), and the remembered camera and sun only return with their
/// scene; `--fresh` ignores the file.
pub fn restore(args: &OpenArgs, path: Option<&Path>) -> Restored {
    let (remembered, problem) = match path.filter(|_| !args.fresh).map(Remembered::read) {
        Some(Ok(remembered)) => (remembered.unwrap_or_default(), None),
        Some(Err(e)) => (Remembered::default(), Some(format!("{e:#}"))),
        None => (Remembered::default(), None),
    };
    let mut options = args.scene.load_options();
    let (spec, spec_remembered) = match (&args.scene.scene, &remembered.scene) {
        (Some(spec), _) => (spec.clone(), false),
        (None, Some(spec)) => {
            options.units = remembered.units;
            (spec.clone(), true)
        }
        (None, None) => (DEFAULT_SCENE.to_owned(), false),
    };
    let same_scene = remembered.scene.as_deref() == Some(spec.as_str());
    Restored {
        camera: same_scene
            .then_some(remembered.camera)
            .flatten()
            .map(|c| (c, remembered.fly_speed_m_per_s)),
        sun: same_scene.then_some(remembered.sun).flatten(),
        spec,
        options,
        spec_remembered,
        frame: remembered.frame,
        screenshot: remembered
            .screenshot_folder
            .map(|folder| (folder, remembered.include_panel)),
        problem,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use render_core::frame::{Method, PcfKernel};

    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "shadowlab-remembered-{name}-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn settings_are_written_and_read_back() {
        let path = folder("round-trip").join("nested").join(FILE_NAME);
        assert_eq!(Remembered::read(&path).expect("no file is fine"), None);
        let mut frame = FrameSettings {
            method: Method::Frag,
            measure: true,
            ..FrameSettings::default()
        };
        frame.shadow.resolution = 4096;
        frame.shadow.pcf = PcfKernel::K5x5;
        frame.overlays.casters = true;
        let remembered = Remembered {
            scene: Some("scenes/diorama.gltf".into()),
            units: Units::Centimetres,
            camera: Some(Camera::look_at(
                glam::Vec3::new(1.0, 2.0, 3.0),
                glam::Vec3::ZERO,
                1.0,
                0.1,
                500.0,
            )),
            fly_speed_m_per_s: Some(12.5),
            sun: Some(Sun::from_azimuth_elevation_deg(120.0, 30.0)),
            frame,
            screenshot_folder: Some("shots".into()),
            include_panel: true,
        };
        remembered.write(&path).expect("written");
        assert_eq!(
            Remembered::read(&path).expect("read"),
            Some(remembered),
            "what was written comes back"
        );
    }

    fn open_args(args: &[&str]) -> OpenArgs {
        use clap::Parser as _;
        let cli = crate::cli::Cli::try_parse_from(
            std::iter::once("shadowlab").chain(args.iter().copied()),
        )
        .expect("valid arguments");
        cli.open
    }

    #[test]
    fn the_command_line_wins_and_the_camera_comes_back_with_its_scene() {
        let path = folder("restore").join(FILE_NAME);
        let camera = Camera::look_at(
            glam::Vec3::new(5.0, 6.0, 7.0),
            glam::Vec3::ZERO,
            1.0,
            0.1,
            90.0,
        );
        let sun = Sun::from_azimuth_elevation_deg(10.0, 20.0);
        Remembered {
            scene: Some("scenes/diorama.gltf".into()),
            units: Units::Centimetres,
            camera: Some(camera),
            fly_speed_m_per_s: Some(3.0),
            sun: Some(sun),
            frame: FrameSettings {
                method: Method::Frag,
                ..FrameSettings::default()
            },
            screenshot_folder: Some("shots".into()),
            include_panel: true,
        }
        .write(&path)
        .expect("written");

        // Nothing named: the last scene, in its unit, with its camera and sun.
        let last = restore(&open_args(&[]), Some(&path));
        assert_eq!(last.spec, "scenes/diorama.gltf");
        assert!(last.spec_remembered);
        assert_eq!(last.options.units, Units::Centimetres);
        assert_eq!(last.camera, Some((camera, Some(3.0))));
        assert_eq!(last.sun, Some(sun));
        assert_eq!(last.frame.method, Method::Frag);
        assert_eq!(last.screenshot, Some(("shots".to_owned(), true)));
        assert_eq!(last.problem, None);

        // Another scene named: its own unit and framing, the settings still remembered.
        let other = restore(&open_args(&["builtin:boxes"]), Some(&path));
        assert_eq!(other.spec, "builtin:boxes");
        assert!(!other.spec_remembered);
        assert_eq!(other.options.units, Units::Metres);
        assert_eq!((other.camera, other.sun), (None, None));
        assert_eq!(other.frame.method, Method::Frag);

        // --fresh: the defaults.
        let fresh = restore(&open_args(&["--fresh"]), Some(&path));
        assert_eq!(fresh.spec, DEFAULT_SCENE);
        assert_eq!(fresh.frame, FrameSettings::default());
        assert_eq!(fresh.camera, None);
    }

    #[test]
    fn an_older_file_with_fewer_fields_reads_with_defaults() {
        let path = folder("older").join(FILE_NAME);
        std::fs::create_dir_all(path.parent().expect("folder")).expect("folder");
        std::fs::write(&path, r#"{ "scene": "builtin:boxes" }"#).expect("written");
        let remembered = Remembered::read(&path).expect("read").expect("a file");
        assert_eq!(remembered.scene.as_deref(), Some("builtin:boxes"));
        assert_eq!(remembered.frame, FrameSettings::default());
    }

    #[test]
    fn a_broken_file_is_named_and_kept_aside() {
        let path = folder("broken").join(FILE_NAME);
        std::fs::create_dir_all(path.parent().expect("folder")).expect("folder");
        std::fs::write(&path, "{ not json").expect("written");
        let message = format!("{:#}", Remembered::read(&path).expect_err("broken"));
        assert!(message.contains(&path.display().to_string()), "{message}");
        assert!(message.contains("settings.json.broken"), "{message}");
        assert!(!path.exists(), "moved aside");
        let kept = std::fs::read_to_string(path.with_extension("json.broken")).expect("kept");
        assert_eq!(kept, "{ not json", "nothing is lost");
    }
}
