//! Perspective light frusta from a point: a spot light's one view along its axis, and a point
//! light's six cube faces. Depth is the usual perspective depth, 0 at the near plane and 1 at
//! the far one, so a texel and a metre of depth both grow with the distance along the view
//! (clip w): the lookup scales them by [`Perspective`].

use glam::Vec3;
use glam::camera::rh::{proj::directx::perspective, view::look_to_mat4};

use super::LightFrustum;

/// The near plane of every punctual view, metres: close enough that a caster touching the
/// light still lands in its map, far enough for 32-bit depth to keep a centimetre at 25 m.
pub const NEAR_M: f32 = 0.05;

/// Texels each map reaches past its cone (a cube face past 45 degrees), so that every tap of
/// a PCF kernel up to 7 wide, at a point on the cone's edge, lands inside the map.
const MARGIN_TEXELS: f32 = 4.0;

/// How a perspective view's texels and depths scale with clip w (the distance along the view).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perspective {
    /// A texel's side per metre of distance, metres.
    pub texel_per_w: f32,
    /// Metres of distance per unit of normalised depth, per w squared: `(f - n) / (n f)`.
    pub range_per_w2: f32,
    pub near_m: f32,
    pub far_m: f32,
    /// Where the light is.
    pub position: Vec3,
}

/// The six faces of a cube map: the axis each looks along and its up vector, in the order
/// +X, -X, +Y, -Y, +Z, -Z (a point light's views, and `layered/light.wgsl`'s face choice).
pub const CUBE_FACES: [(&str, Vec3, Vec3); 6] = [
    ("+X", Vec3::X, Vec3::NEG_Y),
    ("-X", Vec3::NEG_X, Vec3::NEG_Y),
    ("+Y", Vec3::Y, Vec3::Z),
    ("-Y", Vec3::NEG_Y, Vec3::NEG_Z),
    ("+Z", Vec3::Z, Vec3::NEG_Y),
    ("-Z", Vec3::NEG_Z, Vec3::NEG_Y),
];

/// A spot light's view: along `direction` (unit), wide enough for its outer cone (half angle
/// `outer_cone_rad`) and [`MARGIN_TEXELS`] more, out to `far_m`.
pub fn spot_frustum(
    position: Vec3,
    direction: Vec3,
    outer_cone_rad: f32,
    far_m: f32,
    resolution: u32,
) -> LightFrustum {
    let half = outer_cone_rad.clamp(0.01, 1.48);
    let up = if direction.y.abs() > 0.9 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    frustum(position, direction, up, half.tan(), far_m, resolution)
}

/// Face `face` of [`CUBE_FACES`] of a point light at `position`, out to `far_m`.
pub fn cube_face_frustum(position: Vec3, face: usize, far_m: f32, resolution: u32) -> LightFrustum {
    let (_, direction, up) = CUBE_FACES[face % 6];
    frustum(position, direction, up, 1.0, far_m, resolution)
}

/// A square perspective frustum whose map reaches `tan_half` (the tangent of the half angle to
/// cover) plus the margin.
fn frustum(
    position: Vec3,
    direction: Vec3,
    up: Vec3,
    tan_half: f32,
    far_m: f32,
    resolution: u32,
) -> LightFrustum {
    let res = resolution.max(16) as f32;
    // The map's half width t in tangent units, with the margin's texels of 2t / res each
    // beyond `tan_half`: t = tan_half + MARGIN * 2t / res.
    let t = tan_half / (1.0 - 2.0 * MARGIN_TEXELS / res);
    let far = far_m.max(NEAR_M * 4.0);
    let light_from_world = look_to_mat4(position, direction, up);
    let clip_from_light = perspective(2.0 * t.atan(), 1.0, NEAR_M, far);
    let texel_per_w = 2.0 * t / res;
    LightFrustum {
        light_from_world,
        clip_from_light,
        light_clip_from_world: clip_from_light * light_from_world,
        light_direction: direction,
        // The coarsest: at the far plane.
        texel_size_m: [texel_per_w * far; 2],
        depth_range_m: far - NEAR_M,
        covers_whole_scene: false,
        warp: None,
        grid: None,
        perspective: Some(Perspective {
            texel_per_w,
            range_per_w2: (far - NEAR_M) / (NEAR_M * far),
            near_m: NEAR_M,
            far_m: far,
            position,
        }),
    }
}

/// Texels of its mip each tile of a tiled mip (a face finer than 4096 texels) reaches past its
/// share of the face on every side, so that a PCF kernel of a point in its share lands
/// inside it (`virtual_maps/pages.wgsl` `TILE_OVERLAP`).
pub const TILE_OVERLAP_TEXELS: f32 = 8.0;

/// Tile (`column`, `row`) of `tiles` x `tiles` of `full`, a perspective view of `full_side`
/// texels square, as a view of `tile_side` texels: the same light and depths, its projection
/// the tile's share of `full`'s (rows from the top) widened by [`TILE_OVERLAP_TEXELS`] of
/// `full`'s texels each way.
pub fn tile_frustum(
    full: &LightFrustum,
    (column, row): (u32, u32),
    tiles: u32,
    (full_side, tile_side): (u32, u32),
) -> LightFrustum {
    let t = tiles.max(1) as f32;
    // Half the tile's extent in `full`'s normalised device coordinates, and its centre.
    let half = 1.0 / t + 2.0 * TILE_OVERLAP_TEXELS / full_side as f32;
    let centre = glam::Vec2::new(
        -1.0 + (2 * column + 1) as f32 / t,
        1.0 - (2 * row + 1) as f32 / t,
    );
    let window = glam::Mat4::from_cols(
        glam::Vec4::new(1.0 / half, 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, 1.0 / half, 0.0, 0.0),
        glam::Vec4::Z,
        (-centre / half).extend(0.0).extend(1.0),
    );
    let clip_from_light = window * full.clip_from_light;
    let perspective = full.perspective.map(|p| Perspective {
        texel_per_w: p.texel_per_w * half * full_side as f32 / tile_side as f32,
        ..p
    });
    let texel_per_w = perspective.map_or(full.texel_size_m[0], |p| p.texel_per_w);
    let far = perspective.map_or(1.0, |p| p.far_m);
    LightFrustum {
        clip_from_light,
        light_clip_from_world: clip_from_light * full.light_from_world,
        texel_size_m: [texel_per_w * far; 2],
        perspective,
        ..*full
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ndc(frustum: &LightFrustum, p: Vec3) -> Vec3 {
        frustum.light_clip_from_world.project_point3(p)
    }

    #[test]
    fn a_spot_sees_its_cone_with_the_margin_and_depth_runs_from_near_to_far() {
        let f = spot_frustum(Vec3::new(0.0, 5.0, 0.0), Vec3::NEG_Y, 0.5, 20.0, 256);
        // A point on the cone's edge 10 m down lies inside by the margin's texels.
        let edge = Vec3::new(10.0 * 0.5f32.tan(), -5.0, 0.0);
        let x = ndc(&f, edge).x.abs().max(ndc(&f, edge).y.abs());
        let margin = 1.0 - x;
        assert!((margin * 128.0 - MARGIN_TEXELS).abs() < 0.05, "{margin}");
        assert!(ndc(&f, Vec3::new(0.0, 5.0 - NEAR_M, 0.0)).z.abs() < 1e-5);
        assert!((ndc(&f, Vec3::new(0.0, -15.0, 0.0)).z - 1.0).abs() < 1e-5);
        // A metre of distance at w is range_per_w2 * w^2 metres per unit of depth.
        let p = f.perspective.unwrap();
        let (a, b) = (
            ndc(&f, Vec3::new(0.0, -5.0, 0.0)).z,
            ndc(&f, Vec3::new(0.0, -5.01, 0.0)).z,
        );
        let metres_per_unit = 0.01 / (b - a);
        assert!((metres_per_unit / (p.range_per_w2 * 100.0) - 1.0).abs() < 0.01);
    }

    #[test]
    fn the_cube_faces_cover_every_direction_each_point_in_the_face_of_its_major_axis() {
        let light = Vec3::new(1.0, 2.0, 3.0);
        for d in [
            Vec3::new(3.0, 1.0, -2.9),
            Vec3::new(-0.1, 5.0, 4.9),
            Vec3::new(0.2, -0.3, -7.0),
            Vec3::new(-4.0, 3.9, 0.0),
        ] {
            let a = d.abs();
            let face = if a.x >= a.y && a.x >= a.z {
                usize::from(d.x < 0.0)
            } else if a.y >= a.z {
                2 + usize::from(d.y < 0.0)
            } else {
                4 + usize::from(d.z < 0.0)
            };
            let f = cube_face_frustum(light, face, 20.0, 128);
            let p = ndc(&f, light + d);
            assert!(
                p.x.abs() < 1.0 && p.y.abs() < 1.0 && p.z > 0.0 && p.z < 1.0,
                "{d} {p}"
            );
        }
    }

    #[test]
    fn a_tile_is_its_share_of_the_finer_face_with_the_overlap_on_the_same_texel_grid() {
        let light = Vec3::new(1.0, 2.0, 3.0);
        let full = cube_face_frustum(light, 4, 30.0, 16384);
        let tile = tile_frustum(&full, (2, 1), 4, (16384, 4096));
        // Texel coordinates of a world point in the full face and in the tile.
        let texel = |f: &LightFrustum, side: f32, p: Vec3| {
            let n = ndc(f, p);
            (
                glam::Vec2::new(n.x * 0.5 + 0.5, 0.5 - n.y * 0.5) * side,
                n.z,
            )
        };
        let scale = 4096.0 / (4096.0 + 2.0 * TILE_OVERLAP_TEXELS);
        for p in [
            light + Vec3::new(0.3, -0.2, 5.0),
            light + Vec3::new(-2.0, 1.0, 9.0),
            light + Vec3::new(0.01, 0.02, 1.0),
        ] {
            let (f, depth) = texel(&full, 16384.0, p);
            let (t, tile_depth) = texel(&tile, 4096.0, p);
            // The tile's texels start TILE_OVERLAP texels of the face before its share
            // (column 2, row 1 of 4096 each) and are 1 / scale of the face's wide.
            let expected = (f - glam::Vec2::new(2.0 * 4096.0, 4096.0)
                + glam::Vec2::splat(TILE_OVERLAP_TEXELS))
                * scale;
            assert!(
                (t - expected).length() < 0.05,
                "{p}: {t} against {expected}"
            );
            assert!((depth - tile_depth).abs() < 1e-6);
        }
        let (full_p, tile_p) = (full.perspective.unwrap(), tile.perspective.unwrap());
        assert!((tile_p.texel_per_w * scale / full_p.texel_per_w - 1.0).abs() < 1e-5);
    }
}
