//! The overlays' colours, in one place: the shaders read them as the constants of the virtual
//! file `palette.wgsl` ([`wgsl`]), and the legends of the view and of screenshots
//! (`frame::legend`) name them, so a legend always shows the colour the picture uses.

/// A named overlay colour: `PALETTE_<name>` in WGSL, linear RGB in 0..1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Swatch {
    pub name: &'static str,
    pub rgb: [f32; 3],
}

const fn swatch(name: &'static str, rgb: [f32; 3]) -> Swatch {
    Swatch { name, rgb }
}

/// Casters tint and inset stripes: what happened to a caster in the shadow pass.
pub const RENDERED: Swatch = swatch("RENDERED", [0.15, 0.85, 0.25]);
pub const EXCLUDED: Swatch = swatch("EXCLUDED", [0.6, 0.2, 0.9]);
pub const CULLED_LIGHT_FRUSTUM: Swatch = swatch("CULLED_LIGHT_FRUSTUM", [1.0, 0.55, 0.05]);
pub const CULLED_LIGHT_OCCLUSION: Swatch = swatch("CULLED_LIGHT_OCCLUSION", [0.95, 0.85, 0.1]);
/// Culled by the receiver mask, the changed region, the footprint test or the shadow volume.
pub const CULLED_MASK: Swatch = swatch("CULLED_MASK", [0.95, 0.1, 0.75]);
/// Error heat map: the method leaves light where the reference has shadow, and the opposite.
pub const MISSING_SHADOW: Swatch = swatch("MISSING_SHADOW", [1.0, 0.05, 0.05]);
pub const EXTRA_SHADOW: Swatch = swatch("EXTRA_SHADOW", [0.1, 0.35, 1.0]);
/// The light's view: texels no caster covers, and the masks over the map.
pub const MAP_EMPTY: Swatch = swatch("MAP_EMPTY", [0.02, 0.02, 0.08]);
pub const MAP_NEAR: Swatch = swatch("MAP_NEAR", [1.0, 1.0, 1.0]);
pub const MAP_FAR: Swatch = swatch("MAP_FAR", [0.05, 0.05, 0.05]);
pub const MASK_GEOMETRY: Swatch = swatch("MASK_GEOMETRY", [0.1, 0.9, 0.2]);
pub const MASK_BOX: Swatch = swatch("MASK_BOX", [0.15, 0.35, 1.0]);
pub const MASK_FRAGMENT: Swatch = swatch("MASK_FRAGMENT", [1.0, 0.12, 0.1]);
/// Shadow-volume fill heat map: one volume fragment on a pixel, then [`FILL_HIGH`] at
/// [`FILL_HIGH_COUNT`] and more.
pub const FILL_LOW: Swatch = swatch("FILL_LOW", [0.1, 0.3, 1.0]);
pub const FILL_HIGH: Swatch = swatch("FILL_HIGH", [1.0, 0.9, 0.1]);
/// The shadow volumes drawn over the view, translucent (Lloyd et al.'s Figure 1).
pub const VOLUME: Swatch = swatch("VOLUME", [1.0, 0.85, 0.1]);
/// The virtual maps' page view: pages drawn this frame, pages whose movable casters alone were
/// drawn, cached pages read this frame, cached pages no pixel read, and pages the pool
/// refused.
pub const PAGE_DRAWN: Swatch = swatch("PAGE_DRAWN", [1.0, 0.55, 0.1]);
pub const PAGE_REFRESHED: Swatch = swatch("PAGE_REFRESHED", [0.95, 0.9, 0.2]);
pub const PAGE_CACHED: Swatch = swatch("PAGE_CACHED", [0.15, 0.8, 0.3]);
pub const PAGE_IDLE: Swatch = swatch("PAGE_IDLE", [0.25, 0.35, 0.6]);
pub const PAGE_REFUSED: Swatch = swatch("PAGE_REFUSED", [0.95, 0.1, 0.25]);
/// Volume fragments on one pixel that the fill heat map shows as [`FILL_HIGH`].
pub const FILL_HIGH_COUNT: u32 = 1024;

/// The shadow views (cascades) in order; a ninth view takes the first colour again.
pub const VIEWS: [Swatch; 8] = [
    swatch("VIEW_0", [0.9, 0.2, 0.2]),
    swatch("VIEW_1", [0.2, 0.8, 0.25]),
    swatch("VIEW_2", [0.2, 0.4, 1.0]),
    swatch("VIEW_3", [0.95, 0.8, 0.1]),
    swatch("VIEW_4", [0.8, 0.25, 0.9]),
    swatch("VIEW_5", [0.1, 0.85, 0.85]),
    swatch("VIEW_6", [1.0, 0.5, 0.1]),
    swatch("VIEW_7", [0.6, 0.6, 0.6]),
];

const ALL: [Swatch; 21] = [
    RENDERED,
    EXCLUDED,
    CULLED_LIGHT_FRUSTUM,
    CULLED_LIGHT_OCCLUSION,
    CULLED_MASK,
    MISSING_SHADOW,
    EXTRA_SHADOW,
    MAP_EMPTY,
    MAP_NEAR,
    MAP_FAR,
    MASK_GEOMETRY,
    MASK_BOX,
    MASK_FRAGMENT,
    FILL_LOW,
    FILL_HIGH,
    VOLUME,
    PAGE_DRAWN,
    PAGE_REFRESHED,
    PAGE_CACHED,
    PAGE_IDLE,
    PAGE_REFUSED,
];

pub(crate) const WGSL_PATH: &str = "palette.wgsl";

/// The swatches as WGSL constants, for [`WGSL_PATH`].
pub(crate) fn wgsl() -> String {
    use std::fmt::Write as _;
    let mut out = String::from(
        "// Written by palette.rs from the Rust definitions: do not edit, do not copy.\n",
    );
    for Swatch {
        name,
        rgb: [r, g, b],
    } in ALL.iter().chain(&VIEWS)
    {
        let _ = writeln!(
            out,
            "const PALETTE_{name} = vec3<f32>({r:?}, {g:?}, {b:?});"
        );
    }
    let _ = writeln!(
        out,
        "const PALETTE_FILL_HIGH_COUNT: u32 = {FILL_HIGH_COUNT}u;"
    );
    out.push_str("fn palette_view(v: u32) -> vec3<f32> {\n    switch v % 8u {\n");
    for (i, Swatch { name, .. }) in VIEWS.iter().enumerate() {
        let case = if i + 1 == VIEWS.len() {
            "default".to_owned()
        } else {
            format!("case {i}u")
        };
        let _ = writeln!(out, "        {case}: {{ return PALETTE_{name}; }}");
    }
    out.push_str("    }\n}\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_swatch_is_written_once_for_the_shaders() {
        let source = wgsl();
        for Swatch { name, .. } in ALL.iter().chain(&VIEWS) {
            assert_eq!(
                source.matches(&format!("const PALETTE_{name} ")).count(),
                1,
                "{name}"
            );
        }
    }
}
