//! Deterministic camera paths for `bench` and the window's playback: keyframes of eye and
//! target, sampled piecewise linearly. Built-in cities get a street-level path, other scenes an
//! orbit; a path can also be read from a CSV file of `eye_x,eye_y,eye_z,target_x,target_y,target_z`.

use std::fmt::Write as _;

use glam::{Vec2, Vec3};

use super::{CityParams, Scene};
use crate::geom::Aabb;

/// One keyframe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathKey {
    pub eye: Vec3,
    pub target: Vec3,
}

/// A camera path of at least one key.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraPath {
    pub name: String,
    keys: Vec<PathKey>,
}

/// Why a path file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum PathError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}, line {line}: {reason}")]
    Parse {
        path: String,
        line: usize,
        reason: String,
    },
    #[error("{path}: the path has no keyframes")]
    Empty { path: String },
}

/// Eye height of the street-level path, metres (above cars).
const STREET_EYE_HEIGHT_M: f32 = 3.5;

impl CameraPath {
    pub fn new(name: impl Into<String>, keys: Vec<PathKey>) -> Option<Self> {
        (!keys.is_empty()).then(|| Self {
            name: name.into(),
            keys,
        })
    }

    pub fn keys(&self) -> &[PathKey] {
        &self.keys
    }

    /// Eye and target at `u` in `[0, 1]` along the path.
    pub fn sample(&self, u: f32) -> PathKey {
        let last = self.keys.len() - 1;
        if last == 0 || !u.is_finite() {
            return self.keys[0];
        }
        let x = u.clamp(0.0, 1.0) * last as f32;
        let i = (x.floor() as usize).min(last - 1);
        let t = x - i as f32;
        let (a, b) = (self.keys[i], self.keys[i + 1]);
        PathKey {
            eye: a.eye.lerp(b.eye, t),
            target: a.target.lerp(b.target, t),
        }
    }

    /// The length of the eye's path, metres.
    pub fn length_m(&self) -> f32 {
        self.keys
            .windows(2)
            .map(|k| k[0].eye.distance(k[1].eye))
            .sum()
    }

    /// Eye and target `metres` along the eye's path from its first key (clamped to its ends),
    /// so a camera flown at a steady speed covers the same distance every frame however the
    /// keys are spaced. A stretch where only the target moves is passed in no distance: the
    /// view turns at once there.
    pub fn sample_at_distance(&self, metres: f32) -> PathKey {
        let mut left = if metres.is_finite() {
            metres.max(0.0)
        } else {
            0.0
        };
        for k in self.keys.windows(2) {
            let length = k[0].eye.distance(k[1].eye);
            if left < length {
                let t = left / length;
                return PathKey {
                    eye: k[0].eye.lerp(k[1].eye, t),
                    target: k[0].target.lerp(k[1].target, t),
                };
            }
            left -= length;
        }
        self.keys[if metres > 0.0 { self.keys.len() - 1 } else { 0 }]
    }

    /// The default path of a scene: streets for the built-in cities, an orbit otherwise.
    pub fn default_for(scene: &Scene) -> Self {
        match scene.name.as_str() {
            "builtin:city" | "builtin:city-night" => Self::city_streets(&CityParams::full(0)),
            "builtin:city-small" => Self::city_streets(&CityParams::small(0)),
            "builtin:robots" => super::robots::robots_walk(),
            "builtin:corridor" => super::corridor::corridor_walk(),
            "builtin:hall" => super::hall::hall_walk(),
            name => match name
                .strip_prefix("builtin:")
                .and_then(|n| super::sized_city(n, 0))
            {
                Some(params) => Self::city_streets(&params),
                None => Self::orbit(&scene.bounds()),
            },
        }
    }

    /// Street level through the middle of a city: along the central street, then up the
    /// central avenue, looking ahead.
    pub fn city_streets(params: &CityParams) -> Self {
        let (bx, bz) = (params.blocks_x.max(2), params.blocks_z.max(2));
        let row = bz / 2;
        let column = bx / 2;
        // Street centre lines between neighbouring blocks.
        let street_z =
            (params.block_rect(0, row - 1).max.y + params.block_rect(0, row).min.y) * 0.5;
        let avenue_x =
            (params.block_rect(column - 1, 0).max.x + params.block_rect(column, 0).min.x) * 0.5;
        let ground = params.ground_rect();
        let h = STREET_EYE_HEIGHT_M;
        let at = |x: f32, z: f32| Vec3::new(x, h, z);
        let look = 60.0;
        let start_x = ground.min.x + params.street_width_m;
        let end_z = ground.max.y - params.street_width_m;
        let keys = vec![
            PathKey {
                eye: at(start_x, street_z),
                target: at(start_x + look, street_z) + Vec3::Y * 2.0,
            },
            PathKey {
                eye: at(avenue_x - 20.0, street_z),
                target: at(avenue_x + look, street_z) + Vec3::Y * 2.0,
            },
            PathKey {
                eye: at(avenue_x, street_z),
                target: at(avenue_x, street_z + look) + Vec3::Y * 2.0,
            },
            PathKey {
                eye: at(avenue_x, end_z),
                target: at(avenue_x, end_z + look) + Vec3::Y * 2.0,
            },
        ];
        Self {
            name: "city streets".into(),
            keys,
        }
    }

    /// A circle around the scene at a third of its height above the top, looking at the centre.
    pub fn orbit(bounds: &Aabb) -> Self {
        let centre = bounds.center();
        let radius = (bounds.extent().truncate().length() * 0.6).max(1.0);
        let height = bounds.max.y.max(centre.y) + bounds.extent().y * 0.3 + radius * 0.2;
        let keys = (0..=16)
            .map(|k| {
                let angle = k as f32 / 16.0 * std::f32::consts::TAU;
                let offset = Vec2::from_angle(angle) * radius;
                PathKey {
                    eye: Vec3::new(centre.x + offset.x, height, centre.z + offset.y),
                    target: centre,
                }
            })
            .collect();
        Self {
            name: "orbit".into(),
            keys,
        }
    }

    /// Reads a CSV path: one key per line, `#` comments and a header line allowed.
    pub fn from_csv(path: &str, text: &str) -> Result<Self, PathError> {
        let mut keys = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') || line.starts_with("eye") {
                continue;
            }
            let values: Result<Vec<f32>, _> =
                line.split(',').map(|v| v.trim().parse::<f32>()).collect();
            let error = |reason: String| PathError::Parse {
                path: path.to_owned(),
                line: n + 1,
                reason,
            };
            let values = values.map_err(|e| error(format!("{e} in '{line}'")))?;
            if values.len() != 6 || values.iter().any(|v| !v.is_finite()) {
                return Err(error(format!(
                    "expected 6 finite numbers eye_x,eye_y,eye_z,target_x,target_y,target_z, got '{line}'"
                )));
            }
            keys.push(PathKey {
                eye: Vec3::new(values[0], values[1], values[2]),
                target: Vec3::new(values[3], values[4], values[5]),
            });
        }
        Self::new(path, keys).ok_or_else(|| PathError::Empty {
            path: path.to_owned(),
        })
    }

    pub fn load(path: &std::path::Path) -> Result<Self, PathError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| PathError::Io {
            path: name.clone(),
            source,
        })?;
        Self::from_csv(&name, &text)
    }

    pub fn to_csv(&self) -> String {
        let mut out = String::from("eye_x,eye_y,eye_z,target_x,target_y,target_z\n");
        for k in &self.keys {
            let _ = writeln!(
                out,
                "{},{},{},{},{},{}",
                k.eye.x, k.eye.y, k.eye.z, k.target.x, k.target.y, k.target.z
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampling_interpolates_between_keys() {
        let path = CameraPath::new(
            "t",
            vec![
                PathKey {
                    eye: Vec3::ZERO,
                    target: Vec3::X,
                },
                PathKey {
                    eye: Vec3::new(10.0, 0.0, 0.0),
                    target: Vec3::Y,
                },
            ],
        )
        .expect("two keys");
        assert_eq!(path.sample(0.0).eye, Vec3::ZERO);
        assert_eq!(path.sample(1.0).eye, Vec3::new(10.0, 0.0, 0.0));
        assert_eq!(path.sample(0.25).eye, Vec3::new(2.5, 0.0, 0.0));
        assert_eq!(path.sample(f32::NAN).eye, Vec3::ZERO);
    }

    #[test]
    fn sampling_by_distance_covers_equal_metres_whatever_the_keys() {
        let key = |x: f32, target: Vec3| PathKey {
            eye: Vec3::new(x, 0.0, 0.0),
            target,
        };
        // 2 m, then 8 m: by key the first metre would be a quarter of the path.
        let path = CameraPath::new(
            "t",
            vec![key(0.0, Vec3::X), key(2.0, Vec3::Y), key(10.0, Vec3::Z)],
        )
        .expect("three keys");
        assert!((path.length_m() - 10.0).abs() < 1e-6);
        assert_eq!(path.sample_at_distance(1.0).eye, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(
            path.sample_at_distance(1.0).target,
            Vec3::new(0.5, 0.5, 0.0)
        );
        assert_eq!(path.sample_at_distance(6.0).eye, Vec3::new(6.0, 0.0, 0.0));
        assert_eq!(
            path.sample_at_distance(6.0).target,
            Vec3::new(0.0, 0.5, 0.5)
        );
        assert_eq!(path.sample_at_distance(-3.0), path.keys()[0]);
        assert_eq!(path.sample_at_distance(f32::NAN), path.keys()[0]);
        assert_eq!(path.sample_at_distance(25.0), path.keys()[2]);
        // A still path (every key at one eye) stays at its first key until any distance.
        let still = CameraPath::new("s", vec![key(3.0, Vec3::X), key(3.0, Vec3::Y)]).expect("keys");
        assert!(still.length_m().abs() < 1e-6);
        assert_eq!(still.sample_at_distance(0.0), still.keys()[0]);
    }

    #[test]
    fn csv_round_trips_and_errors_name_the_line() {
        let city = CameraPath::city_streets(&CityParams::small(0));
        let parsed = CameraPath::from_csv("p.csv", &city.to_csv()).expect("own output parses");
        assert_eq!(parsed.keys(), city.keys());
        let err = CameraPath::from_csv("p.csv", "# header\n1,2,3,4,5\n").expect_err("five numbers");
        assert!(err.to_string().contains("p.csv, line 2"), "{err}");
        assert!(CameraPath::from_csv("p.csv", "").is_err());
    }

    #[test]
    fn city_street_path_stays_in_the_streets_at_eye_height() {
        let params = CityParams::full(0);
        let path = CameraPath::city_streets(&params);
        for k in 0..=50 {
            let key = path.sample(k as f32 / 50.0);
            assert!((key.eye.y - STREET_EYE_HEIGHT_M).abs() < 1e-3);
            for i in 0..params.blocks_x {
                for j in 0..params.blocks_z {
                    let block = params.block_rect(i, j);
                    let inside = key.eye.x > block.min.x
                        && key.eye.x < block.max.x
                        && key.eye.z > block.min.y
                        && key.eye.z < block.max.y;
                    assert!(
                        !inside,
                        "path key {k} at {} is inside block ({i}, {j})",
                        key.eye
                    );
                }
            }
        }
    }
}
