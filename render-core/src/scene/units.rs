//! The length unit of a scene file's coordinates. Everything inside shadowlab is in metres (the
//! biases, the texel sizes, the camera's speed), so a file in centimetres is scaled on load, and
//! a scene whose size suggests another unit gets a note that says which.

use std::fmt;
use std::str::FromStr;

use glam::{Mat4, Vec3};

use super::Scene;

/// A file's length unit.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum Units {
    #[default]
    Metres,
    Centimetres,
    Millimetres,
    Inches,
}

impl Units {
    pub const ALL: [Self; 4] = [
        Self::Metres,
        Self::Centimetres,
        Self::Millimetres,
        Self::Inches,
    ];

    /// The name the command line and the panel use: `m`, `cm`, `mm`, `in`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Metres => "m",
            Self::Centimetres => "cm",
            Self::Millimetres => "mm",
            Self::Inches => "in",
        }
    }

    pub fn metres_per_unit(self) -> f32 {
        match self {
            Self::Metres => 1.0,
            Self::Centimetres => 0.01,
            Self::Millimetres => 0.001,
            Self::Inches => 0.0254,
        }
    }
}

impl fmt::Display for Units {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Units {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|u| u.name() == s)
            .ok_or_else(|| format!("unknown unit '{s}' (available: m, cm, mm, in)"))
    }
}

/// The scene with coordinates in `units` turned into metres (every instance scaled about the
/// origin; meshes are shared and stay as they are). For imported files: scripted motions (the
/// built-in scenes', which are in metres) are not carried over.
pub fn in_metres(scene: Scene, units: Units) -> Scene {
    if units == Units::Metres {
        return scene;
    }
    let to_metres = Mat4::from_scale(Vec3::splat(units.metres_per_unit()));
    let Scene {
        name,
        meshes,
        mut instances,
        sun,
        ..
    } = scene;
    for inst in &mut instances {
        inst.world_from_local = to_metres * inst.world_from_local;
        inst.aabb_in_world = meshes[inst.mesh as usize]
            .aabb_in_local
            .transformed(&inst.world_from_local);
    }
    Scene::new(name, meshes, instances, sun)
}

/// A scene larger than this, read in metres, is more likely centimetres or millimetres.
const LARGE_M: f32 = 2000.0;
/// A scene smaller than this, read in a unit below metres, is more likely metres.
const SMALL_M: f32 = 0.05;

/// A note when the scene's size (already in metres, read as `units`) suggests another unit.
pub fn unit_note(scene: &Scene, units: Units) -> Option<String> {
    let bounds = scene.bounds();
    let extent = (bounds.max - bounds.min).max_element();
    if !extent.is_finite() || extent <= 0.0 {
        return None;
    }
    let suggest = |other: Units| {
        let size = extent / units.metres_per_unit() * other.metres_per_unit();
        format!(
            "the scene is {} across read in {units}; if its unit is {other} it is {}: open it \
             with --units {other} (or choose {other} under Scene, Units)",
            metres(extent),
            metres(size),
        )
    };
    if units == Units::Metres && extent > LARGE_M {
        let other = if extent > 100.0 * LARGE_M {
            Units::Millimetres
        } else {
            Units::Centimetres
        };
        return Some(suggest(other));
    }
    if units != Units::Metres && extent < SMALL_M {
        return Some(suggest(Units::Metres));
    }
    None
}

fn metres(m: f32) -> String {
    if m >= 1000.0 {
        format!("{:.1} km", m / 1000.0)
    } else if m >= 1.0 {
        format!("{m:.1} m")
    } else {
        format!("{:.1} cm", m * 100.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Instance, Mesh, Sun};

    /// A unit quad stretched to `size` units along x.
    fn strip(size: f32) -> Scene {
        let mesh = Mesh::new(
            "strip",
            vec![
                Vec3::ZERO,
                Vec3::new(size, 0.0, 0.0),
                Vec3::new(size, 0.0, 1.0),
            ],
            None,
            vec![0, 1, 2],
        );
        let instance = Instance::new("strip", 0, &mesh, Mat4::IDENTITY);
        Scene::new("test:strip", vec![mesh], vec![instance], Sun::default())
    }

    #[test]
    fn a_centimetre_file_becomes_metres() {
        let scene = in_metres(strip(3500.0), Units::Centimetres);
        let b = scene.bounds();
        assert!(
            (b.max.x - 35.0).abs() < 1e-4 && (b.max.z - 0.01).abs() < 1e-6,
            "{b:?}"
        );
        assert_eq!(unit_note(&scene, Units::Centimetres), None);
    }

    #[test]
    fn the_size_suggests_the_unit() {
        // The diorama: 35 m in centimetres, read as metres.
        let note = unit_note(&strip(3500.0), Units::Metres).expect("a note");
        assert!(
            note.contains("3.5 km") && note.contains("--units cm") && note.contains("35.0 m"),
            "{note}"
        );
        let note = unit_note(&strip(350_000.0), Units::Metres).expect("a note");
        assert!(note.contains("--units mm"), "{note}");
        // A 1.2 m table read as millimetres is 1.2 mm.
        let note = unit_note(
            &in_metres(strip(1.2), Units::Millimetres),
            Units::Millimetres,
        )
        .expect("a note");
        assert!(
            note.contains("--units m ") && note.contains("1.2 m"),
            "{note}"
        );
        assert_eq!(unit_note(&strip(900.0), Units::Metres), None);
        assert_eq!("cm".parse::<Units>(), Ok(Units::Centimetres));
        assert!(
            "feet"
                .parse::<Units>()
                .unwrap_err()
                .contains("m, cm, mm, in")
        );
    }
}
