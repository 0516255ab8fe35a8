//! How the virtual shadow maps (`virtual_maps/`) are set: the physical pool, the clipmap's
//! levels and finest texel, resolution matching's bias and the cache. Plain data: the UI
//! edits it, the CLI parses it, reports echo it.

use serde::{Deserialize, Serialize};

/// Texels along a page's side.
pub const PAGE_TEXELS: u32 = 128;
/// Pages along a clipmap level's side: a level is a virtual map of 32 x 32 pages, 4096
/// texels square, centred on the camera.
pub const LEVEL_PAGES: u32 = 32;
/// Bytes of one physical page (`Depth32Float`).
pub const PAGE_BYTES: u64 = (PAGE_TEXELS * PAGE_TEXELS * 4) as u64;

/// The widest cone, from its axis to its edge, whose spot light's virtual maps are one chain
/// of mips along it: a wider cone's one view would spread its texels over more than a cube
/// face's 90 degrees (and past about 85 degrees no one perspective view holds it), so it
/// takes a point light's cube, pixels outside the cone still reading no page.
pub const SPOT_CHAIN_MAX_CONE_RAD: f32 = std::f32::consts::FRAC_PI_4;

/// The cone of `light` when the virtual maps cast it through one chain along the cone; `None`
/// where they use the cube (a point light, or a spot wider than
/// [`SPOT_CHAIN_MAX_CONE_RAD`]).
pub fn spot_chain(light: &crate::scene::PointShadow) -> Option<crate::scene::SpotCone> {
    light
        .cone
        .filter(|c| c.outer_rad <= SPOT_CHAIN_MAX_CONE_RAD)
}

/// The virtual maps a user sets.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct VirtualSettings {
    /// Physical pages in the pool (`--pages`): 1,024 pages are 64 MiB, the memory of four
    /// cascades of 2048.
    pub pages: u32,
    /// Clipmap levels (`--levels`), level k's texel 2^k times the finest.
    pub levels: u32,
    /// The finest level's texel, metres.
    pub finest_texel_m: f32,
    /// Added to the level resolution matching picks, in octaves: above 0 coarser, below
    /// finer (Unreal's `ResolutionLodBiasDirectional`, whose default, -0.5, this takes: texels
    /// half a pixel wide to two thirds of one, so a PCF edge spans fewer pixels).
    pub lod_bias: f32,
    /// Pages persist across frames until something moves through them (`--cache`).
    pub cache: bool,
    /// Each physical page keeps static casters' depths apart from movable ones', so a moving
    /// object redraws only the movable casters of the pages it touches (Unreal's
    /// `Cache.StaticSeparate`, `--separate-static`): twice the pool's memory.
    pub separate_static: bool,
    /// Casters are culled per block of 16 x 16 texels that visible pixels read, not per page
    /// (Unreal 5.6's receiver mask, `--receiver-mask`): only in the layer drawn again anyway
    /// (every caster's with one layer or where every page is invalid, the movable casters'
    /// with static casters apart); a page the mask left a caster out of is drawn again the
    /// next frame.
    pub receiver_mask: bool,
    /// With static casters apart: a movable caster wholly behind a cached page's static
    /// depths (the farthest of each block of 16 x 16 texels it covers) neither makes the
    /// page's movable layer stale when it moves nor is drawn into it (Unreal's invalidations
    /// and casters culled against the static pages' depths, `--static-occlusion`). Exact: the
    /// nearer depth of both layers, all the light reads, stays the same at every texel.
    pub static_occlusion: bool,
}

impl Default for VirtualSettings {
    fn default() -> Self {
        Self {
            pages: 1024,
            levels: 16,
            finest_texel_m: 0.002,
            lod_bias: -0.5,
            cache: true,
            separate_static: false,
            receiver_mask: false,
            static_occlusion: true,
        }
    }
}

impl VirtualSettings {
    pub const MIN_PAGES: u32 = 16;
    /// 256 MiB of pages: beyond that a page pass dispatches more workgroups than one
    /// dimension holds (16,384 pages asked for 131,072 of at most 65,535). A pool beyond the
    /// device's largest texture is fitted to it, and the notes say so.
    pub const MAX_PAGES: u32 = 4096;
    pub const MAX_LEVELS: u32 = 24;

    /// Whether static occlusion works: it needs static casters apart.
    pub fn static_occlusion_applies(&self) -> bool {
        self.separate_static && self.static_occlusion
    }

    /// Depth layers of a physical page: 2 when static casters are kept apart.
    pub fn page_layers(&self) -> u32 {
        1 + u32::from(self.separate_static)
    }

    /// The pool's memory, MiB.
    pub fn pool_mib(&self) -> f64 {
        (u64::from(self.pages * self.page_layers()) * PAGE_BYTES) as f64 / (1024.0 * 1024.0)
    }

    /// These settings within their ranges (the pool within what the device's textures hold).
    #[must_use]
    pub fn clamped(self, max_texture_side: u32) -> Self {
        let side_pages = max_texture_side / PAGE_TEXELS;
        Self {
            pages: self.pages.clamp(
                Self::MIN_PAGES,
                Self::MAX_PAGES.min(side_pages * side_pages / self.page_layers()),
            ),
            levels: self.levels.clamp(1, Self::MAX_LEVELS),
            finest_texel_m: if self.finest_texel_m.is_finite() && self.finest_texel_m > 0.0 {
                self.finest_texel_m
            } else {
                Self::default().finest_texel_m
            },
            lod_bias: if self.lod_bias.is_finite() {
                self.lod_bias.clamp(-4.0, 4.0)
            } else {
                0.0
            },
            cache: self.cache,
            separate_static: self.separate_static,
            receiver_mask: self.receiver_mask,
            static_occlusion: self.static_occlusion,
        }
    }

    /// Pages along the physical atlas's side, columns and rows of one layer: as square as
    /// the pool allows with its layers one below the other.
    pub fn atlas_pages(&self) -> [u32; 2] {
        let columns = (f64::from(self.pages * self.page_layers()).sqrt().ceil() as u32).max(1);
        [columns, self.pages.div_ceil(columns)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_pool_holds_the_memory_of_four_cascades_of_2048() {
        let s = VirtualSettings::default();
        assert_eq!(u64::from(s.pages) * PAGE_BYTES, 4 * 2048 * 2048 * 4);
        assert!((s.pool_mib() - 64.0).abs() < 1e-12);
        assert_eq!(s.atlas_pages(), [32, 32]);
    }

    #[test]
    fn the_pool_fits_the_device_and_odd_sizes_make_a_whole_atlas() {
        let s = VirtualSettings {
            pages: 4096,
            ..VirtualSettings::default()
        };
        assert_eq!(s.clamped(8192).pages, 4096);
        assert_eq!(s.clamped(2048).pages, 256);
        let odd = VirtualSettings { pages: 1000, ..s };
        let [c, r] = odd.atlas_pages();
        assert!(c * r >= 1000 && c * (r - 1) < 1000, "{c} x {r}");
        assert_eq!(VirtualSettings { pages: 1, ..s }.clamped(8192).pages, 16);
        let apart = VirtualSettings {
            separate_static: true,
            ..s
        };
        assert_eq!(apart.clamped(8192).pages, 2048, "two layers of 8192 x 4096");
        assert!(
            (VirtualSettings {
                pages: 512,
                ..apart
            }
            .pool_mib()
                - 64.0)
                .abs()
                < 1e-12
        );
        for side in [2048, 4096, 8192] {
            for pages in VirtualSettings::MIN_PAGES..=VirtualSettings::MAX_PAGES {
                for separate_static in [false, true] {
                    let s = VirtualSettings {
                        pages,
                        separate_static,
                        ..s
                    }
                    .clamped(side);
                    let [c, r] = s.atlas_pages();
                    assert!(c * r >= s.pages, "{s:?}");
                    assert!(
                        c * PAGE_TEXELS <= side && r * s.page_layers() * PAGE_TEXELS <= side,
                        "{s:?} on {side}: {c} x {r}"
                    );
                }
            }
        }
    }
}
