//! The scene's punctual lights as shadow views and as the records the light term sums: a spot
//! light is one view, a point light six (cube faces, `geom::CUBE_FACES`). Where each view
//! renders is the path's choice (`targets.rs`).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::geom::{self, LightFrustum};
use crate::scene::{LightKind, PunctualLight, Scene, Sun};

/// How far a light without a range reaches, as a multiple of the scene's diagonal.
const UNBOUNDED_REACH: f32 = 1.0;

/// One light for the light term (`layered/light.wgsl` `LightRecord`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LightRecord {
    /// xyz: position; w: range in metres (0: none, falling off with distance squared).
    pub position_range: [f32; 4],
    /// rgb: colour times intensity over the sun's illuminance (candela per lux); w: cosine of
    /// the inner cone (full light inside it).
    pub color_inner: [f32; 4],
    /// xyz: the spot's direction; w: cosine of the outer cone (no light outside it), -2 for a
    /// point light.
    pub spot: [f32; 4],
    /// x: the light's first view; y: its views (1 spot, 6 point); z, w: unused.
    pub views: [u32; 4],
}
const _: () = assert!(size_of::<LightRecord>() == 64);

/// One light's views, before the path places them.
pub struct LightViews {
    /// "spot 3" or "point 1 +X", per view.
    pub names: Vec<String>,
    pub frusta: Vec<LightFrustum>,
    pub records: Vec<LightRecord>,
}

/// The first `count` lights of `scene` (0: all), their views with maps `resolution` square and
/// their records.
pub fn light_views(scene: &Scene, count: u32, resolution: u32) -> LightViews {
    let take = if count == 0 {
        scene.lights.len()
    } else {
        (count as usize).min(scene.lights.len())
    };
    let reach = scene.bounds().diagonal_length().max(1.0) * UNBOUNDED_REACH;
    let mut out = LightViews {
        names: Vec::new(),
        frusta: Vec::new(),
        records: Vec::new(),
    };
    for (i, light) in scene.lights.iter().take(take).enumerate() {
        let far = light.range.filter(|r| *r > 0.0).unwrap_or(reach);
        let first = out.frusta.len() as u32;
        match light.kind {
            LightKind::Spot {
                direction,
                outer_cone_rad,
                ..
            } => {
                let direction = direction.try_normalize().unwrap_or(Vec3::NEG_Y);
                out.names.push(format!("spot {i}"));
                out.frusta.push(geom::spot_frustum(
                    light.position,
                    direction,
                    outer_cone_rad,
                    far,
                    resolution,
                ));
            }
            LightKind::Point => {
                for (face, (name, _, _)) in geom::CUBE_FACES.iter().enumerate() {
                    out.names.push(format!("point {i} {name}"));
                    out.frusta.push(geom::cube_face_frustum(
                        light.position,
                        face,
                        far,
                        resolution,
                    ));
                }
            }
        }
        let views = out.frusta.len() as u32 - first;
        out.records.push(record(light, [first, views]));
    }
    out
}

fn record(light: &PunctualLight, [first, views]: [u32; 2]) -> LightRecord {
    let scale = (light.intensity / Sun::ILLUMINANCE_LX).max(0.0);
    let (direction, cos_inner, cos_outer) = match light.kind {
        LightKind::Spot {
            direction,
            inner_cone_rad,
            outer_cone_rad,
        } => (
            direction.try_normalize().unwrap_or(Vec3::NEG_Y),
            inner_cone_rad.min(outer_cone_rad).cos(),
            outer_cone_rad.cos(),
        ),
        LightKind::Point => (Vec3::ZERO, -2.0, -2.0),
    };
    LightRecord {
        position_range: light.position.extend(light.range.unwrap_or(0.0)).to_array(),
        color_inner: [
            light.color[0] * scale,
            light.color[1] * scale,
            light.color[2] * scale,
            cos_inner,
        ],
        spot: direction.extend(cos_outer).to_array(),
        views: [first, views, 0, 0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Instance, Mesh, Scene, Sun};

    fn scene_with(lights: Vec<PunctualLight>) -> Scene {
        let mesh = Mesh::new(
            "tri",
            vec![Vec3::ZERO, Vec3::X, Vec3::Z],
            None,
            vec![0, 1, 2],
        );
        let instance = Instance::new("tri", 0, &mesh, glam::Mat4::IDENTITY);
        let mut scene = Scene::new(
            "t",
            vec![mesh],
            vec![instance],
            Sun::from_direction(Vec3::Y),
        );
        scene.lights = lights;
        scene
    }

    fn light(name: &str, kind: LightKind) -> PunctualLight {
        PunctualLight {
            name: name.into(),
            position: Vec3::new(0.0, 4.0, 0.0),
            kind,
            color: [1.0, 0.5, 0.25],
            intensity: 1000.0,
            range: Some(12.0),
        }
    }

    #[test]
    fn a_spot_is_one_view_a_point_six_and_the_records_name_their_first_view() {
        let spot = LightKind::Spot {
            direction: Vec3::new(0.0, -2.0, 0.0),
            inner_cone_rad: 0.3,
            outer_cone_rad: 0.4,
        };
        let scene = scene_with(vec![
            light("a", LightKind::Point),
            light("b", spot),
            light("c", LightKind::Point),
        ]);
        let all = light_views(&scene, 0, 256);
        assert_eq!(all.frusta.len(), 13);
        assert_eq!(all.names[0], "point 0 +X");
        assert_eq!(all.names[6], "spot 1");
        assert_eq!(all.names[12], "point 2 -Z");
        let firsts: Vec<[u32; 2]> = all
            .records
            .iter()
            .map(|r| [r.views[0], r.views[1]])
            .collect();
        assert_eq!(firsts, [[0, 6], [6, 1], [7, 6]]);
        // The spot's direction is unit and its cones are cosines; intensity over the sun's lux.
        let s = &all.records[1];
        assert_eq!(&s.spot[..3], &[0.0, -1.0, 0.0]);
        assert!((s.spot[3] - 0.4f32.cos()).abs() < 1e-6);
        assert!((s.color_inner[3] - 0.3f32.cos()).abs() < 1e-6);
        assert!((s.color_inner[0] - 1000.0 / Sun::ILLUMINANCE_LX).abs() < 1e-9);
        assert!(all.records[0].spot[3] < -1.5, "a point light has no cone");
        // The first two lights only.
        let two = light_views(&scene, 2, 256);
        assert_eq!((two.frusta.len(), two.records.len()), (7, 2));
    }
}
