//! The levels of a point or spot light: a chain of mips per cube face, or one along a spot's
//! cone, the mips finer than a level's 4096 texels cut into tiles of 4096, a level each.

use super::VirtualTechnique;

use crate::geom::{CUBE_FACES, LightFrustum, cube_face_frustum, spot_frustum, tile_frustum};
use crate::scene::PointShadow;
use crate::shadow_view::{LEVEL_PAGES, PAGE_TEXELS, ShadowView, ViewTarget, spot_chain};

/// Mips of each face of a point light's cube (or of a spot's one chain) at most: 16,384
/// texels square down to 128, one page, so that the coarsest pages hold every point the light
/// reaches (the fallback of pixels whose pages the pool refused). Fewer keep the coarsest:
/// six are faces of 4096.
pub const POINT_MIPS: u32 = 8;

/// Texels along a side of mip `mip` of a chain of `mips` mips: the coarsest is one page.
pub const fn mip_side(mip: u32, mips: u32) -> u32 {
    PAGE_TEXELS << (mips - 1 - mip)
}

/// Tiles along a side of mip `mip` of a chain of `mips`: a level holds 4096 texels square (its
/// table 32 x 32 pages), so the mips finer than that are cut into tiles of 4096, a level each
/// (`pages.wgsl` `mip_tiles`).
pub const fn mip_tiles(mip: u32, mips: u32) -> u32 {
    let tiles = mip_side(mip, mips) / (LEVEL_PAGES * PAGE_TEXELS);
    if tiles > 1 { tiles } else { 1 }
}

/// The levels of a face's chain of `mips` mips: its tiles.
pub const fn face_levels(mips: u32) -> u32 {
    let mut levels = 0;
    let mut mip = 0;
    while mip < mips {
        levels += mip_tiles(mip, mips) * mip_tiles(mip, mips);
        mip += 1;
    }
    levels
}
const _: () = assert!(6 * face_levels(POINT_MIPS) as usize == super::gpu_data::LEVEL_SLOTS);

impl VirtualTechnique {
    /// A point light's levels: each face of its cube (`CUBE_FACES`' order) a chain of mips,
    /// 16,384 texels square (with all eight), 8192, ..., down to one page, out to the scene's
    /// farthest corner, the mips finer than 4096 as tiles of 4096 (`mip_tiles`,
    /// `geom::tile_frustum`); a spot light's, one chain along its cone where it is no wider
    /// than `SPOT_CHAIN_MAX_CONE_RAD`. Their pages stay where they are (no window moves with
    /// the camera).
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
                let side = mip_side(mip, self.face_mips);
                let full = frustum(side);
                let tiles = mip_tiles(mip, self.face_mips);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chain_keeps_its_coarsest_mips_and_tiles_those_finer_than_a_level() {
        // Eight mips: 16,384 texels as 4 x 4 tiles, 8192 as 2 x 2, then 4096 down to 128.
        let sides: Vec<u32> = (0..8).map(|m| mip_side(m, 8)).collect();
        assert_eq!(sides, [16384, 8192, 4096, 2048, 1024, 512, 256, 128]);
        let tiles: Vec<u32> = (0..8).map(|m| mip_tiles(m, 8)).collect();
        assert_eq!(tiles, [4, 2, 1, 1, 1, 1, 1, 1]);
        assert_eq!(face_levels(8), 26);
        // Six: faces of 4096, a level a mip; one: the single page.
        assert_eq!((mip_side(0, 6), face_levels(6)), (4096, 6));
        assert_eq!((mip_side(0, 1), face_levels(1)), (128, 1));
    }
}
