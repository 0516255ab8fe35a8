//! A clipmap level of a directional light's virtual shadow map: a square of whole pages
//! centred on the camera, on a texel grid fixed in light space, so a page keeps its place
//! (and its cached depths) as the camera moves, and only pages that leave the square are lost.

use glam::{DVec3, Vec3};

use super::light_fit::{LightSpace, TexelGrid};
use super::{Aabb, LightFrustum};

/// One level's light frustum and where its square lies on the level's page grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipmapLevel {
    pub light: LightFrustum,
    /// The absolute page grid position of the square's first page: its column (along the
    /// light's x) and row (down the map, against the light's y), so that a page's absolute
    /// position is this plus its page in the square, whatever the square's position.
    pub first_page: [i32; 2],
}

/// Level with texels `texel_m` wide, `pages` pages of `page_texels` texels on a side, centred
/// on `eye`; depth over the whole scene along the light, which the camera does not change.
pub fn fit_clipmap_level(
    direction_to_sun: Vec3,
    scene_bounds: &Aabb,
    eye: Vec3,
    texel_m: f64,
    (pages, page_texels): (u32, u32),
) -> ClipmapLevel {
    let space = LightSpace::new(direction_to_sun, scene_bounds);
    let centre = space.to_light(eye.as_dvec3());
    let page_m = texel_m * f64::from(page_texels);
    let half = f64::from(pages / 2);
    let first = |axis: usize| {
        let c = centre[axis] / page_m;
        // A camera past what an i32 page index holds keeps the grid at the scene.
        if c.is_finite() && c.abs() < 1e9 {
            c.floor() - half
        } else {
            -half
        }
    };
    let (fx, fy) = (first(0), first(1));
    let scene = space.scene_extent;
    let z_margin = (scene.1.z - scene.0.z).abs() * 1e-3 + 1e-2;
    let side = f64::from(pages) * page_m;
    let min = DVec3::new(fx * page_m, fy * page_m, scene.0.z - z_margin);
    let max = DVec3::new(min.x + side, min.y + side, scene.1.z + z_margin);
    let resolution = pages * page_texels;
    ClipmapLevel {
        light: LightFrustum {
            grid: Some(TexelGrid::of(min, texel_m, resolution)),
            ..space.frustum((min, max), resolution, false)
        },
        first_page: [fx as i32, -(fy as i32) - pages as i32],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn level(eye: Vec3, texel: f64) -> ClipmapLevel {
        let scene = Aabb::new(
            Vec3::new(-100.0, 0.0, -100.0),
            Vec3::new(100.0, 30.0, 100.0),
        );
        fit_clipmap_level(
            Vec3::new(0.3, 0.8, 0.2).normalize(),
            &scene,
            eye,
            texel,
            (32, 128),
        )
    }

    /// The texel (x right, y down the map) where the level's grid places `p`, as
    /// `light_clip` and `shadow_lookup` do in WGSL.
    fn texel_of(l: &ClipmapLevel, p: Vec3) -> [f64; 2] {
        let g = l.light.grid.expect("a clipmap level has a grid");
        let rows = l.light.light_from_world.transpose();
        let light = [
            f64::from(rows.x_axis.truncate().dot(p) + l.light.light_from_world.w_axis.x),
            f64::from(rows.y_axis.truncate().dot(p) + l.light.light_from_world.w_axis.y),
        ];
        let half = 2048.0;
        [
            light[0] * f64::from(g.per_metre[0]) - f64::from(g.centre_texel[0]) + half,
            half - (light[1] * f64::from(g.per_metre[1]) - f64::from(g.centre_texel[1])),
        ]
    }

    /// A point's absolute page: the square's first page plus the page it falls in.
    fn absolute_page(l: &ClipmapLevel, p: Vec3) -> [i64; 2] {
        let t = texel_of(l, p);
        [
            i64::from(l.first_page[0]) + (t[0] / 128.0).floor() as i64,
            i64::from(l.first_page[1]) + (t[1] / 128.0).floor() as i64,
        ]
    }

    #[test]
    fn a_point_keeps_its_absolute_page_as_the_camera_moves() {
        let p = Vec3::new(3.3, 1.0, -7.9);
        let a = level(Vec3::new(0.0, 2.0, 0.0), 0.01);
        let b = level(Vec3::new(9.0, 2.0, -14.0), 0.01);
        assert_ne!(a.first_page, b.first_page, "the square moved");
        assert_eq!(absolute_page(&a, p), absolute_page(&b, p));
        // Texel positions differ by whole pages.
        let (ta, tb) = (texel_of(&a, p), texel_of(&b, p));
        for axis in 0..2 {
            let pages = (ta[axis] - tb[axis]) / 128.0;
            assert!((pages - pages.round()).abs() < 1e-3, "{ta:?} {tb:?}");
        }
    }

    #[test]
    fn the_camera_lies_near_the_middle_of_its_square() {
        let eye = Vec3::new(12.0, 2.0, 5.0);
        let l = level(eye, 0.02);
        let t = texel_of(&l, eye);
        for axis in t {
            assert!((1920.0..=2176.0).contains(&axis), "{t:?}");
        }
        assert!(l.light.texel_size_m.iter().all(|t| (t - 0.02).abs() < 1e-7));
    }
}
