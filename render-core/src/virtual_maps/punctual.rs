//! The levels of a point or spot light: a chain of mips per cube face, or one along a spot's
//! cone, the mips finer than a level's 4096 texels cut into tiles of 4096, a level each.

use super::VirtualTechnique;

use crate::geom::{CUBE_FACES, LightFrustum, cube_face_frustum, spot_frustum, tile_frustum};
use crate::scene::PointShadow;
use crate::shadow_view::{LEVEL_PAGES, PAGE_TEXELS, ShadowView, ViewTarget, spot_chain};

/// Mips of each face of a point light's cube (or of a spot's one chain) at most: 16,384
/// texels square down to 128, one page, so that the coarsest pages hold every point the light
/// reaches (the fallback of pixels whose pages the pool refused).
pub const POINT_MIPS: u32 = 8;

/// A face's finest mip, texels square (Unreal's local lights' virtual maps are as fine).
const FINEST_FACE_TEXELS: u32 = (LEVEL_PAGES * PAGE_TEXELS) << 2;

/// Tiles along a side of mip `mip` of a face: a level holds 4096 texels square (its table 32 x
/// 32 pages), so the mips finer than that are cut into tiles of 4096, a level each
/// (`pages.wgsl` `mip_tiles`).
pub const fn mip_tiles(mip: u32) -> u32 {
    let tiles = (FINEST_FACE_TEXELS >> mip) / (LEVEL_PAGES * PAGE_TEXELS);
    if tiles > 1 { tiles } else { 1 }
}

/// The levels of a face's chain of `mips` mips: its tiles.
pub const fn face_levels(mips: u32) -> u32 {
    let mut levels = 0;
    let mut mip = 0;
    while mip < mips {
        levels += mip_tiles(mip) * mip_tiles(mip);
        mip += 1;
    }
    levels
}
const _: () = assert!(6 * face_levels(POINT_MIPS) as usize == super::gpu_data::LEVEL_SLOTS);

impl VirtualTechnique {
    /// A point light's levels: each face of its cube (`CUBE_FACES`' order) a chain of mips,
    /// 16,384 texels square, 8192, ..., out to the scene's farthest corner, the mips finer than
    /// 4096 as tiles of 4096 (`mip_tiles`, `geom::tile_frustum`); a spot light's, one
    /// chain along its cone where it is no wider than `SPOT_CHAIN_MAX_CONE_RAD`. Their pages
    /// stay where they are (no window moves with the camera).
    pub(super) fn punctual_views(
        &mut self,
        light: PointShadow,
        bounds: &crate::geom::Aabb,
    ) -> Vec<ShadowView> {
        let position = light.position;
        let far = bounds
            .corners()
            .iter()
            .map(|c| c.distance(position))
            .fold(0.0f32, f32::max)
            * 1.001
            + 0.1;
        let mut views = Vec::new();
        let mut chain = |name: &str, frustum: &dyn Fn(u32) -> LightFrustum| {
            for mip in 0..self.face_mips {
                let side = FINEST_FACE_TEXELS >> mip;
                let full = frustum(side);
                let tiles = mip_tiles(mip);
                let tile_side = side / tiles;
                for row in 0..tiles {
                    for column in 0..tiles {
                        let (label, view) = if tiles == 1 {
                            (format!("{name} mip {mip}"), full)
                        } else {
                            let tile = tile_frustum(&full, (column, row), tiles, (side, tile_side));
                            (format!("{name} mip {mip} tile {column},{row}"), tile)
                        };
                        self.first_pages.push([0, 0]);
                        views.push(ShadowView::covering_all_depths(
                            &label,
                            view,
                            ViewTarget::layer(0, tile_side),
                        ));
                    }
                }
            }
        };
        match spot_chain(&light) {
            Some(cone) => chain("spot", &|side| {
                spot_frustum(position, cone.direction, cone.outer_rad, far, side)
            }),
            None => {
                for (face, (name, _, _)) in CUBE_FACES.iter().enumerate() {
                    chain(&format!("point {name}"), &|side| {
                        cube_face_frustum(position, face, far, side)
                    });
                }
            }
        }
        views
    }

    /// Chains of levels that may shade a point (`pages.wgsl` `chain_count`): the sun's
    /// clipmap, a point light's six faces, or a spot light's one.
    pub(super) fn chains(&self) -> u32 {
        self.settings
            .levels
            .checked_div(face_levels(self.face_mips))
            .unwrap_or(1)
    }
}
