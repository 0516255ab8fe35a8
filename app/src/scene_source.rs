//! Opening scenes by the names users type: `builtin:NAME` or a glTF path.

use std::path::Path;

use anyhow::Context as _;
use glam::Vec3;
use render_core::geom::{Aabb, Camera};
use render_core::scene::{
    BUILTIN_SCENES, CITY_BLOCKS, ChunkSettings, Scene, Units, import_gltf, in_metres, load_builtin,
    unit_note,
};

/// How a scene is opened: the built-ins' seed, the chunking of huge objects, a file's unit.
#[derive(Clone, Copy, Debug, Default)]
pub struct LoadOptions {
    pub seed: u64,
    pub chunking: ChunkSettings,
    pub units: Units,
    /// Every object this many times in its place (0 or 1: once).
    pub copies: u32,
}

/// A loaded scene and what the user should know about it (a unit that looks wrong).
pub struct Loaded {
    pub scene: Scene,
    pub notes: Vec<String>,
}

/// Loads `spec` (see [`load_scene_in_file_units`]) in metres, with notes on its unit.
pub fn load_scene(spec: &str, options: &LoadOptions) -> anyhow::Result<Loaded> {
    let scene = load_scene_in_file_units(spec, options)?.with_copies(options.copies);
    if spec.starts_with("builtin:") {
        let notes = (options.units != Units::Metres)
            .then(|| {
                format!(
                    "built-in scenes are in metres: --units {} does not apply",
                    options.units
                )
            })
            .into_iter()
            .collect();
        return Ok(Loaded { scene, notes });
    }
    let scene = in_metres(scene, options.units);
    let notes = unit_note(&scene, options.units).into_iter().collect();
    Ok(Loaded { scene, notes })
}

/// Loads `spec`: `builtin:NAME` (see `shadowlab scenes`) or a `.gltf` / `.glb` path.
fn load_scene_in_file_units(spec: &str, options: &LoadOptions) -> anyhow::Result<Scene> {
    if let Some(name) = spec.strip_prefix("builtin:") {
        return load_builtin(name, options.seed).with_context(|| {
            let names: Vec<_> = BUILTIN_SCENES
                .iter()
                .map(|s| format!("builtin:{}", s.name))
                .collect();
            format!(
                "unknown built-in scene '{spec}' (available: {}, and builtin:city:N for N x N \
                 blocks, N from {} to {})",
                names.join(", "),
                CITY_BLOCKS.start(),
                CITY_BLOCKS.end()
            )
        });
    }
    let path = Path::new(spec);
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(extension.as_deref(), Some("gltf" | "glb")) {
        anyhow::bail!("{spec}: not a scene; expected builtin:NAME or a .gltf / .glb file");
    }
    Ok(import_gltf(path, &options.chunking)?)
}

/// A camera that sees the whole box, from the south-west and above: the closest distance along
/// that direction at which all eight corners project inside the view. The near plane is small
/// (depth is reversed, so precision holds) and the far plane reaches past the box.
pub fn frame_scene(bounds: &Aabb, aspect: f32, fov_y_rad: f32) -> Camera {
    let bounds = if bounds.is_empty() {
        Aabb::new(Vec3::splat(-1.0), Vec3::ONE)
    } else {
        *bounds
    };
    let radius = (bounds.diagonal_length() * 0.5).max(0.5);
    let direction = Vec3::new(-0.6, 0.55, 0.6).normalize();
    let near = (radius * 1e-4).clamp(0.01, 0.1);
    let aspect = if aspect.is_finite() && aspect > 0.0 {
        aspect
    } else {
        1.5
    };
    let camera_at = |distance: f32| {
        let eye = bounds.center() + direction * distance;
        Camera::look_at(
            eye,
            bounds.center(),
            fov_y_rad,
            near,
            distance + radius * 2.0,
        )
    };
    let sees_all = |camera: &Camera| {
        let m = camera.clip_from_world(aspect);
        bounds.corners().iter().all(|c| {
            let p = m.project_point3(*c);
            p.x.abs() <= 0.98 && p.y.abs() <= 0.98 && p.z > 0.0 && p.z <= 1.0
        })
    };
    // The bounding sphere's distance always works; search for the closest that still does.
    let (mut lo, mut hi) = (
        0.0f32,
        radius / (fov_y_rad.min(fov_y_rad * aspect) * 0.5).sin().max(1e-3),
    );
    for _ in 0..32 {
        let mid = (lo + hi) * 0.5;
        if sees_all(&camera_at(mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    camera_at(hi)
}
