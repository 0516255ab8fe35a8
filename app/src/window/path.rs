//! Camera paths in the window: recording the camera while the user flies (a key every tenth of
//! a second, saved as the CSV that `bench --path` and `report --path` read), and playing one
//! back (the last recorded, else the scene's own path).

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use render_core::geom::Camera;
use render_core::scene::{CameraPath, PathKey};

use super::Running;

/// Seconds between recorded keys, and between keys when a recorded path plays.
const KEY_INTERVAL_S: f32 = 0.1;
/// A path made of few keys (the scenes' own) plays at this speed, metres per second.
const PLAY_SPEED_M_S: f32 = 15.0;

/// The camera's keys while recording.
#[derive(Debug, Default)]
pub struct PathRecorder {
    keys: Vec<PathKey>,
    since_key_s: f32,
}

impl PathRecorder {
    /// Keeps the camera as a key once `KEY_INTERVAL_S` has passed since the last (the first at
    /// once).
    pub fn record(&mut self, dt_s: f32, camera: &Camera) {
        self.since_key_s += dt_s.max(0.0);
        if self.keys.is_empty() || self.since_key_s >= KEY_INTERVAL_S {
            self.since_key_s = 0.0;
            self.keys.push(PathKey {
                eye: camera.eye,
                target: camera.eye + camera.forward,
            });
        }
    }

    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// The recorded path, named `name`; none without a key.
    pub fn finish(self, name: &str) -> Option<CameraPath> {
        CameraPath::new(name, self.keys)
    }
}

/// A path playing: where along it the camera is.
#[derive(Debug)]
pub struct PathPlayer {
    path: CameraPath,
    elapsed_s: f32,
    duration_s: f32,
    /// A path of few keys is flown at `PLAY_SPEED_M_S` by distance; a recorded one key by key,
    /// as it was recorded.
    by_distance: bool,
    /// The last key was given.
    ended: bool,
}

impl PathPlayer {
    pub fn new(path: CameraPath) -> Self {
        let recorded_s = (path.keys().len() - 1) as f32 * KEY_INTERVAL_S;
        let flown_s = path.length_m() / PLAY_SPEED_M_S;
        Self {
            path,
            elapsed_s: 0.0,
            duration_s: recorded_s.max(flown_s).max(KEY_INTERVAL_S),
            by_distance: flown_s > recorded_s,
            ended: false,
        }
    }

    pub fn name(&self) -> &str {
        &self.path.name
    }

    /// The key now, then `dt_s` later; the last key once the time is up, then none.
    pub fn advance(&mut self, dt_s: f32) -> Option<PathKey> {
        if self.ended {
            return None;
        }
        let u = (self.elapsed_s / self.duration_s).min(1.0);
        self.ended = u >= 1.0;
        let key = if self.by_distance {
            self.path
                .sample_at_distance(u * self.duration_s * PLAY_SPEED_M_S)
        } else {
            self.path.sample(u)
        };
        self.elapsed_s += dt_s.max(0.0);
        Some(key)
    }
}

/// Writes `path` as CSV into `folder` (created when missing), named by the time.
pub fn save(path: &CameraPath, folder: &Path) -> anyhow::Result<PathBuf> {
    std::fs::create_dir_all(folder)
        .with_context(|| format!("creating folder {}", folder.display()))?;
    let stamp = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let file = folder.join(format!("shadowlab-path-{stamp}.csv"));
    std::fs::write(&file, path.to_csv()).with_context(|| format!("writing {}", file.display()))?;
    Ok(file)
}

impl Running {
    /// Starts recording, or stops and saves what was recorded beside the screenshots.
    pub(super) fn toggle_recording(&mut self) {
        let Some(recorder) = self.recorder.take() else {
            self.player = None;
            self.recorder = Some(PathRecorder::default());
            self.message = Some("Recording the camera's path: fly, then stop".into());
            return;
        };
        let Some(path) = recorder.finish("recorded") else {
            return;
        };
        match save(&path, Path::new(&self.screenshot_settings.folder)) {
            Ok(file) => {
                self.message = Some(format!(
                    "Saved a path of {} keys to {}: `shadowlab bench --path {0}` and `report \
                     --path` fly it",
                    path.keys().len(),
                    file.display()
                ));
                self.last_path_file = Some(file.display().to_string());
            }
            Err(e) => {
                log::error!("saving the path: {e:#}");
                self.message = Some(format!("Could not save the path: {e:#}"));
            }
        }
        self.recorded = Some((self.facts.name.clone(), path));
    }

    /// Plays the last recorded path (else the scene's own), or stops playing.
    pub(super) fn toggle_playing(&mut self) {
        if self.player.take().is_some() {
            return;
        }
        self.recorder = None;
        // A path recorded in another scene would fly through nothing.
        let path = self
            .recorded
            .as_ref()
            .filter(|(scene, _)| *scene == self.facts.name)
            .map_or_else(|| CameraPath::default_for(&self.scene), |(_, p)| p.clone());
        self.player = Some(PathPlayer::new(path));
    }

    /// Moves the camera along a playing path, or records it; after the controller's move.
    pub(super) fn follow_path(&mut self, dt_s: f32) {
        if let Some(player) = &mut self.player {
            match player.advance(dt_s) {
                Some(key) => {
                    let c = self.controller.camera;
                    self.controller.camera =
                        Camera::look_at(key.eye, key.target, c.fov_y_rad, c.near_m, c.far_m)
                            .with_up(c.world_up);
                }
                None => self.player = None,
            }
        }
        if let Some(recorder) = &mut self.recorder {
            recorder.record(dt_s, &self.controller.camera);
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    fn camera_at(x: f32) -> Camera {
        Camera::look_at(
            Vec3::new(x, 2.0, 0.0),
            Vec3::new(x + 1.0, 2.0, 0.0),
            1.0,
            0.1,
            100.0,
        )
    }

    #[test]
    fn a_recorded_path_keeps_a_key_each_tenth_of_a_second_and_reads_back_from_its_file() {
        let mut recorder = PathRecorder::default();
        // 60 frames of 1/60 s while flying 1 m a frame: the first at once, then every 0.1 s.
        for frame in 0..60 {
            recorder.record(1.0 / 60.0, &camera_at(frame as f32));
        }
        assert!(
            (10..=11).contains(&recorder.len()),
            "{} keys",
            recorder.len()
        );
        let path = recorder.finish("recorded").expect("keys");
        assert_eq!(path.keys()[0].eye, Vec3::new(0.0, 2.0, 0.0));
        assert!((path.keys()[0].target - Vec3::new(1.0, 2.0, 0.0)).length() < 1e-5);
        let folder = std::env::temp_dir().join(format!("shadowlab-paths-{}", std::process::id()));
        let file = save(&path, &folder).expect("saved");
        let read = CameraPath::load(&file).expect("bench reads it");
        assert_eq!(read.keys().len(), path.keys().len());
        for (a, b) in read.keys().iter().zip(path.keys()) {
            assert!((a.eye - b.eye).length() < 1e-3 && (a.target - b.target).length() < 1e-3);
        }
        assert!(PathRecorder::default().finish("none").is_none());
    }

    #[test]
    fn a_path_plays_from_its_first_key_to_its_last_and_ends() {
        let keys: Vec<PathKey> = (0..11)
            .map(|k| PathKey {
                eye: Vec3::new(k as f32, 0.0, 0.0),
                target: Vec3::new(k as f32 + 1.0, 0.0, 0.0),
            })
            .collect();
        let mut player = PathPlayer::new(CameraPath::new("line", keys).expect("keys"));
        let first = player.advance(0.5).expect("playing");
        assert_eq!(first.eye, Vec3::ZERO);
        let mut last = first;
        while let Some(key) = player.advance(0.1) {
            assert!(key.eye.x >= last.eye.x, "forward only");
            last = key;
        }
        assert!(
            (last.eye.x - 10.0).abs() < 1e-3,
            "ends at the last key: {last:?}"
        );
        assert!(player.advance(0.1).is_none());
    }

    #[test]
    fn a_path_of_few_keys_plays_at_fifteen_metres_a_second_however_its_keys_are_spaced() {
        let key = |x: f32| PathKey {
            eye: Vec3::new(x, 0.0, 0.0),
            target: Vec3::new(x, 0.0, 1.0),
        };
        // 30 m, then 270 m: by key, half the time would go to the first 30 m.
        let path = CameraPath::new("few", vec![key(0.0), key(30.0), key(300.0)]).expect("keys");
        let mut player = PathPlayer::new(path);
        let mut eyes = Vec::new();
        while let Some(key) = player.advance(1.0) {
            eyes.push(key.eye.x);
        }
        assert_eq!(eyes.len(), 21, "{eyes:?}");
        for (second, x) in eyes.iter().enumerate() {
            assert!((x - 15.0 * second as f32).abs() < 1e-3, "{eyes:?}");
        }
    }
}
