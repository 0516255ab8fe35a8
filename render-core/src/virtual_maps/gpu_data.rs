//! The GPU mirror of the virtual maps' parameters and the word offsets of their counters.
//! Keep in sync with `virtual_maps/pages.wgsl` and `virtual_maps/tables.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Levels the parameters and counters hold: the sun's clipmap's at most
/// (`VirtualSettings::MAX_LEVELS`, 24), or a point light's six faces of eight mips, 26 levels
/// each with the finest two as tiles (`punctual.rs` `face_levels`).
pub(super) const LEVEL_SLOTS: usize = 156;
const _: () = assert!(crate::shadow_view::VirtualSettings::MAX_LEVELS as usize <= LEVEL_SLOTS);

/// `VirtualParams` in `pages.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(super) struct VirtualParams {
    /// Levels, physical pages, the atlas's columns of pages, 1 when every page is invalid.
    pub counts: [u32; 4],
    /// The finest texel (m), the level bias (octaves), moved boxes, the atlas's rows of pages.
    pub tuning: [f32; 4],
    /// Physical pages kept back for fallback pages; 1 when static casters are kept apart;
    /// bit 0 when the receiver mask culls, bit 1 when static casters occlude; mips per face
    /// of a point light's cube (0: the sun).
    pub limits: [u32; 4],
    /// Per level, the absolute position of its square's first page.
    pub first_page: [[i32; 4]; LEVEL_SLOTS],
}
const _: () = assert!(size_of::<VirtualParams>() == 48 + 16 * LEVEL_SLOTS);

/// Word offsets in `Counters` (`tables.wgsl`).
pub(super) mod word {
    use super::LEVEL_SLOTS;

    pub const MARKED: usize = 0;
    pub const RESIDENT: usize = 1;
    pub const RENDERED: usize = 2;
    pub const REFUSED: usize = 3;
    pub const FREE: usize = 4;
    pub const PAIRS: usize = 6;
    pub const DRAWS: usize = 7;
    pub const OVERFLOW: usize = 8;
    pub const EVICTED: usize = 9;
    pub const INVALIDATED: usize = 11;
    pub const CLEAR_ARGS: usize = 12;
    pub const LEVEL_MARKED: usize = 16;
    pub const LEVEL_RENDERED: usize = LEVEL_MARKED + LEVEL_SLOTS;
    pub const LEVEL_PAIRS: usize = LEVEL_RENDERED + LEVEL_SLOTS;
    pub const RECTS: usize = LEVEL_PAIRS + LEVEL_SLOTS;
    pub const TEXELS_SAMPLED: usize = RECTS + 4 * LEVEL_SLOTS;
    pub const REFRESHED: usize = TEXELS_SAMPLED + 1;
    pub const MASK_CULLED: usize = REFRESHED + 2;
    pub const CULL_SPANNED: usize = MASK_CULLED + 1;
    pub const CULL_READS: usize = CULL_SPANNED + 1;
    pub const OCCLUSION_SPARED: usize = CULL_READS + 1;
    pub const OCCLUSION_CULLED: usize = OCCLUSION_SPARED + 1;
    /// When measuring, per level its (caster, page) pairs in the per-page oracle, copied
    /// from the oracle's buffer (`draw.wgsl` `oracle`).
    pub const LEVEL_ORACLE: usize = OCCLUSION_CULLED + 1;
    /// Words in all.
    pub const COUNT: usize = LEVEL_ORACLE + LEVEL_SLOTS;
}

/// The pages' counts of one frame, as the GPU left them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct FrameCounts {
    pub marked: u32,
    pub resident: u32,
    pub rendered: u32,
    /// Cached pages whose movable casters' layer alone was drawn again.
    pub refreshed: u32,
    /// (caster, page) pairs the receiver mask left out.
    pub mask_culled: u32,
    /// The cull: page flags under the casters' boxes, and the flags and hierarchy cells read.
    pub cull_spanned: u32,
    pub cull_reads: u32,
    /// Static occlusion: (moved box, page) pairs that left the page's movable layer fresh,
    /// and (movable caster, refreshed page) pairs left out.
    pub occlusion_spared: u32,
    pub occlusion_culled: u32,
    pub refused: u32,
    /// Free physical pages before allocation (after the eviction, where one ran).
    pub free: u32,
    pub pairs: u32,
    pub draws: u32,
    pub overflow: u32,
    pub evicted: u32,
    pub invalidated: u32,
    pub texels_sampled: u32,
    pub level_marked: Vec<u32>,
    pub level_rendered: Vec<u32>,
    pub level_pairs: Vec<u32>,
    /// When measuring, per level the pairs drawn that hold a texel a visible pixel's tap
    /// reads shadowed (the per-page oracle).
    pub level_oracle: Vec<u32>,
}

impl FrameCounts {
    pub fn from_words(words: &[u32], levels: usize) -> Option<Self> {
        if words.len() < word::COUNT {
            return None;
        }
        let per_level = |first: usize| words[first..first + levels.min(LEVEL_SLOTS)].to_vec();
        Some(Self {
            marked: words[word::MARKED],
            resident: words[word::RESIDENT],
            rendered: words[word::RENDERED],
            refreshed: words[word::REFRESHED],
            mask_culled: words[word::MASK_CULLED],
            cull_spanned: words[word::CULL_SPANNED],
            cull_reads: words[word::CULL_READS],
            occlusion_spared: words[word::OCCLUSION_SPARED],
            occlusion_culled: words[word::OCCLUSION_CULLED],
            refused: words[word::REFUSED],
            free: words[word::FREE],
            pairs: words[word::PAIRS],
            draws: words[word::DRAWS],
            overflow: words[word::OVERFLOW],
            evicted: words[word::EVICTED],
            invalidated: words[word::INVALIDATED],
            texels_sampled: words[word::TEXELS_SAMPLED],
            level_marked: per_level(word::LEVEL_MARKED),
            level_rendered: per_level(word::LEVEL_RENDERED),
            level_pairs: per_level(word::LEVEL_PAIRS),
            level_oracle: per_level(word::LEVEL_ORACLE),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::LEVEL_SLOTS;
    use crate::virtual_maps::oracle::{DYNAMIC_ONLY, ENTRY_BITS};
    use crate::virtual_maps::resources::HIERARCHY_CELLS;

    /// The constants the shaders repeat by hand are the ones Rust sizes their buffers by.
    #[test]
    fn the_shaders_hold_the_levels_cells_tiles_and_near_plane_of_the_rust_side() {
        let pages = include_str!("pages.wgsl");
        let tables = include_str!("tables.wgsl");
        assert!(pages.contains(&format!("first_page: array<vec4<i32>, {LEVEL_SLOTS}>")));
        assert_eq!(
            tables
                .matches(&format!("atomic<u32>, {LEVEL_SLOTS}>"))
                .count(),
            3,
            "level_marked, level_rendered, level_pairs"
        );
        assert!(tables.contains(&format!("array<atomic<u32>, 4>, {LEVEL_SLOTS}>")));
        assert!(pages.contains(&format!("DYNAMIC_ONLY: u32 = {DYNAMIC_ONLY:#010x}u;")));
        assert!(pages.contains(&format!("ENTRY_BITS: u32 = {ENTRY_BITS:#010x}u;")));
        let draw = include_str!("draw.wgsl");
        assert!(draw.contains(&format!("ORACLE_LEVELS: u32 = {LEVEL_SLOTS}u;")));
        assert!(tables.contains(&format!("HIERARCHY_CELLS: u32 = {HIERARCHY_CELLS}u;")));
        assert!(pages.contains(&format!("POINT_NEAR_M: f32 = {:?};", crate::geom::NEAR_M)));
        let overlap = crate::geom::TILE_OVERLAP_TEXELS;
        assert!(pages.contains(&format!("TILE_OVERLAP: f32 = {overlap:?};")));
        let side = crate::shadow_view::LEVEL_PAGES * crate::shadow_view::PAGE_TEXELS;
        assert!(pages.contains(&format!("LEVEL_TEXELS: i32 = {side};")));
    }
}
