//! The GPU encoding of culling's vocabulary, in one place: method bits, counter slots, outcome
//! codes, state and selection bits, mask values. The shaders read them as the constants of
//! the virtual file `culling/codes.wgsl`, which [`wgsl`] writes from these definitions.

use super::Method;
use super::stage::{CasterOutcome, StageKind};

/// Which parts of the GPU pipeline a method uses (`METHOD_*`).
pub(crate) mod method_bits {
    pub const OCCLUSION: u32 = 1;
    pub const MASK: u32 = 2;
    /// Visible receivers drawn in the first phase, with their mask (GEOM, FRAG).
    pub const DRAW_RECEIVERS: u32 = 4;
    pub const ORACLE: u32 = 8;
    /// Last frame's light-visible casters drawn first (occlusion's temporal coherence).
    pub const TEMPORAL: u32 = 16;
    /// Receivers mark the mask with their geometry (GEOM), their boxes (BVOL), or by what was
    /// visible in the light's view last frame (both: GEOM+BVOL).
    pub const GEOM: u32 = 32;
    pub const BVOL: u32 = 64;
    /// The mask holds, per texel, the depth a caster must be nearer than to matter (FRAG).
    pub const FRAG: u32 = 128;
    /// DigitalRune: the caster's shadow volume against the camera's frustum and depth,
    /// extruded to the far plane, or with PROGRESSIVE to the farthest depth behind it in the
    /// light's view (which may be too short).
    pub const VOLUME: u32 = 256;
    pub const PROGRESSIVE: u32 = 512;
    /// Bittner 5.1: the map persists; the mask is the moving objects' old and new boxes,
    /// which are cleared and redrawn.
    pub const INCREMENTAL: u32 = 1024;
    /// The casters the cheap tests kept are rasterised as boxes in the light's view against
    /// the map's depth and the mask, and drawn only where a texel passes.
    pub const FOOTPRINT: u32 = 2048;
    /// The footprint test rasterises the candidates' own triangles, not their boxes: for
    /// masks that leave few candidates (FRAG's depths, `incr`'s changed region), where it
    /// costs little and is exact.
    pub const GEOMETRY_FOOTPRINT: u32 = 4096;

    /// The methods that draw a raster mask (BVOL's boxes, GEOM's geometry, `incr`'s changed
    /// region); FRAG's mask is its depths alone.
    pub const RASTER_MASK: u32 = BVOL | GEOM | INCREMENTAL;

    pub(super) const NAMES: [(&str, u32); 13] = [
        ("OCCLUSION", OCCLUSION),
        ("MASK", MASK),
        ("DRAW_RECEIVERS", DRAW_RECEIVERS),
        ("ORACLE", ORACLE),
        ("TEMPORAL", TEMPORAL),
        ("GEOM", GEOM),
        ("BVOL", BVOL),
        ("FRAG", FRAG),
        ("VOLUME", VOLUME),
        ("PROGRESSIVE", PROGRESSIVE),
        ("INCREMENTAL", INCREMENTAL),
        ("FOOTPRINT", FOOTPRINT),
        ("GEOMETRY_FOOTPRINT", GEOMETRY_FOOTPRINT),
    ];
}

/// Counter slots per view after the stage kinds' own (`StageKind::slot`).
pub(crate) const SLOT_RENDERED: u32 = StageKind::ALL.len() as u32;
pub(crate) const SLOT_TRIANGLES: u32 = SLOT_RENDERED + 1;
pub(crate) const SLOT_FIRST_PHASE: u32 = SLOT_RENDERED + 2;
/// Counters per view.
pub(crate) const COUNTER_SLOTS: u32 = SLOT_RENDERED + 3;

/// Outcome codes, the low byte of an object's state word (and of the CPU methods' outcome
/// buffer): then `OUTCOME_CULLED + StageKind::slot`.
pub(crate) const OUTCOME_NOT_CASTER: u32 = 0;
pub(crate) const OUTCOME_RENDERED: u32 = 1;
pub(crate) const OUTCOME_EXCLUDED: u32 = 2;
const OUTCOME_CULLED: u32 = 3;
/// Within a frame only: the cheap tests kept the caster, its footprint test is to come.
const OUTCOME_PENDING: u32 = STATE_OUTCOME_BITS;

/// The state word: the outcome code in these bits, then flags and the progressive far end.
pub(crate) const STATE_OUTCOME_BITS: u32 = 0xff;
const STATE_LIGHT_VISIBLE: u32 = 1 << 8;
const STATE_FIRST_PHASE: u32 = 1 << 9;
/// Set by the footprint pass where a texel of the caster's box passed.
const STATE_FOOTPRINT_HIT: u32 = 1 << 10;
/// Bits 16-31: the progressive shadow volume's far end found last frame, in 1/65535 of the
/// light's depth range (rounded up).
const STATE_EXTENT_SHIFT: u32 = 16;

/// Per view and instance, in the selection words.
pub(crate) const SELECTION_ORACLE: u32 = 1;
pub(crate) const SELECTION_EXCLUDED: u32 = 2;

/// What the mask raster holds where boxes and geometry marked it: beyond every caster's
/// depth, so only coverage counts; different, so the inset can colour them.
const MASK_MARKED_BOX: f32 = 2.0;
const MASK_MARKED_GEOMETRY: f32 = 3.0;

/// Vertices of one receiver box's outline in a mask (`culling/masks.wgsl` `vs_box`): the
/// convex hull of its 8 corners widened by a square has at most 12 corners, a fan of 10
/// triangles.
pub(crate) const BOX_OUTLINE_VERTICES: u32 = 30;

/// The outcome code of `kind` culling an object.
pub(crate) fn culled_code(kind: StageKind) -> u32 {
    OUTCOME_CULLED + kind.slot()
}

/// The code of `outcome` under `method`, whose stages the outcome's index refers to.
pub(crate) fn outcome_code(outcome: CasterOutcome, method: Method) -> u32 {
    match outcome {
        CasterOutcome::NotACaster => OUTCOME_NOT_CASTER,
        CasterOutcome::Rendered => OUTCOME_RENDERED,
        CasterOutcome::Excluded => OUTCOME_EXCLUDED,
        CasterOutcome::Culled { stage } => stage
            .checked_sub(1)
            .and_then(|k| method.stages().get(k))
            .map_or(OUTCOME_CULLED, |kind| culled_code(*kind)),
    }
}

/// The outcome a state word's code stands for under `method` (stage indices as the report
/// lists `method`'s stages, after "scene casters").
pub(crate) fn outcome_from_code(word: u32, method: Method) -> CasterOutcome {
    match word & STATE_OUTCOME_BITS {
        OUTCOME_NOT_CASTER => CasterOutcome::NotACaster,
        OUTCOME_RENDERED => CasterOutcome::Rendered,
        OUTCOME_EXCLUDED => CasterOutcome::Excluded,
        code => {
            let stages = method.stages();
            let index = stages
                .iter()
                .position(|k| culled_code(*k) == code)
                .unwrap_or(stages.len());
            CasterOutcome::Culled { stage: index + 1 }
        }
    }
}

/// The virtual file `culling/codes.wgsl`.
pub(crate) const WGSL_PATH: &str = "culling/codes.wgsl";

/// The constants above as WGSL, for [`WGSL_PATH`].
pub(crate) fn wgsl() -> String {
    use std::fmt::Write as _;
    let mut out = String::from(
        "// Written by culling/codes.rs from the Rust definitions: do not edit, do not copy.\n",
    );
    let mut constant = |name: &str, value: String| {
        let _ = writeln!(out, "const {name} = {value};");
    };
    for (name, bit) in method_bits::NAMES {
        constant(&format!("METHOD_{name}"), format!("{bit}u"));
    }
    constant(
        "METHODS_RASTER_MASK",
        format!("{}u", method_bits::RASTER_MASK),
    );
    for kind in StageKind::ALL {
        constant(
            &format!("SLOT_{}", kind.wgsl_name()),
            format!("{}u", kind.slot()),
        );
        constant(
            &format!("OUTCOME_CULLED_{}", kind.wgsl_name()),
            format!("{}u", culled_code(kind)),
        );
    }
    for (name, value) in [
        ("SLOT_RENDERED", SLOT_RENDERED),
        ("SLOT_TRIANGLES", SLOT_TRIANGLES),
        ("SLOT_FIRST_PHASE", SLOT_FIRST_PHASE),
        ("COUNTER_SLOTS", COUNTER_SLOTS),
        ("OUTCOME_NOT_CASTER", OUTCOME_NOT_CASTER),
        ("OUTCOME_RENDERED", OUTCOME_RENDERED),
        ("OUTCOME_EXCLUDED", OUTCOME_EXCLUDED),
        ("OUTCOME_PENDING", OUTCOME_PENDING),
        ("STATE_OUTCOME_BITS", STATE_OUTCOME_BITS),
        ("STATE_LIGHT_VISIBLE", STATE_LIGHT_VISIBLE),
        ("STATE_FIRST_PHASE", STATE_FIRST_PHASE),
        ("STATE_FOOTPRINT_HIT", STATE_FOOTPRINT_HIT),
        ("STATE_EXTENT_SHIFT", STATE_EXTENT_SHIFT),
        ("SELECTION_ORACLE", SELECTION_ORACLE),
        ("SELECTION_EXCLUDED", SELECTION_EXCLUDED),
        ("BOX_OUTLINE_VERTICES", BOX_OUTLINE_VERTICES),
    ] {
        constant(name, format!("{value}u"));
    }
    constant("MASK_MARKED_BOX", format!("{MASK_MARKED_BOX:?}"));
    constant("MASK_MARKED_GEOMETRY", format!("{MASK_MARKED_GEOMETRY:?}"));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_is_distinct_and_round_trips() {
        let mut codes: Vec<u32> = StageKind::ALL.iter().map(|k| culled_code(*k)).collect();
        codes.extend([
            OUTCOME_NOT_CASTER,
            OUTCOME_RENDERED,
            OUTCOME_EXCLUDED,
            OUTCOME_PENDING,
        ]);
        let count = codes.len();
        codes.sort_unstable();
        codes.dedup();
        assert_eq!(codes.len(), count, "two outcomes share a code");
        assert!(codes.iter().all(|c| *c <= STATE_OUTCOME_BITS));
        for method in Method::ALL {
            for k in 0..=method.stages().len() {
                let outcome = if k == 0 {
                    CasterOutcome::Rendered
                } else {
                    CasterOutcome::Culled { stage: k }
                };
                assert_eq!(
                    outcome_from_code(outcome_code(outcome, method), method),
                    outcome,
                    "{}",
                    method.name()
                );
            }
        }
        let bits: Vec<u32> = method_bits::NAMES.iter().map(|(_, b)| *b).collect();
        assert!(bits.iter().all(|b| b.is_power_of_two()));
        assert_eq!(
            bits.iter().fold(0, |a, b| a | b).count_ones() as usize,
            bits.len()
        );
    }
}
