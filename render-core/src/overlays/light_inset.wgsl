// The light's view inset: one shadow view's map as grey (near the sun bright), its receiver
// mask in Bittner's colours (BVOL boxes blue, GEOM geometry green, FRAG texels red), and,
// where the reference map shows a caster the method culled, thin stripes in the colour of the
// stage that culled it (overlays/outcome_colours.wgsl, as the camera's `casters` tint).
// Keep in sync with overlays/light_inset.rs.
#import overlays/outcome_colours.wgsl

// The view's layer of the method's and the reference's maps, and of the mask raster.
@group(0) @binding(0) var shadow_map: texture_depth_2d;
@group(0) @binding(1) var reference_ids: texture_2d<u32>;
// Per view and instance, the outcome code in the low byte.
@group(0) @binding(2) var<storage, read> outcomes: array<u32>;
@group(0) @binding(3) var mask_raster: texture_2d<f32>;
@group(0) @binding(4) var<storage, read> mask_bits: array<u32>;
@group(0) @binding(5) var<uniform> inset: Inset;

struct Inset {
    // x: SHOW_* bits; y: shadow texels per mask texel; z: the view's first outcome; w: its
    // first mask word.
    show: vec4<u32>,
    // x, y: the view's first texel in the layer; z: its side in texels; w: the mask's side.
    square: vec4<u32>,
}

const SHOW_RASTER_MASK: u32 = 1u;
const SHOW_FRAGMENT_MASK: u32 = 2u;
const SHOW_OUTCOMES: u32 = 4u;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

@vertex
fn vs_fullscreen(@builtin(vertex_index) index: u32) -> VsOut {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    var out: VsOut;
    out.clip = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    out.uv = uv;
    return out;
}

@fragment
fn fs_light_view(in: VsOut) -> @location(0) vec4<f32> {
    let size = vec2<f32>(f32(inset.square.z));
    let local = vec2<u32>(clamp(in.uv * size, vec2<f32>(0.0), size - 1.0));
    let texel = inset.square.xy + local;
    let depth = textureLoad(shadow_map, texel, 0);
    let near = pow(clamp(1.0 - depth, 0.0, 1.0), 2.0);
    let cleared = depth >= 1.0;
    var colour = select(mix(PALETTE_MAP_FAR, PALETTE_MAP_NEAR, near), PALETTE_MAP_EMPTY, cleared);

    let m = local / max(inset.show.y, 1u);
    var mask = vec3<f32>(0.0);
    if ((inset.show.x & SHOW_RASTER_MASK) != 0u) {
        let marked = textureLoad(mask_raster, m, 0).x;
        if (marked >= MASK_MARKED_GEOMETRY) {
            mask = PALETTE_MASK_GEOMETRY;
        } else if (marked >= MASK_MARKED_BOX) {
            mask = PALETTE_MASK_BOX;
        }
    }
    if ((inset.show.x & SHOW_FRAGMENT_MASK) != 0u) {
        let width = inset.square.w;
        if (bitcast<f32>(mask_bits[inset.show.w + m.y * width + m.x]) > 0.0) {
            mask = PALETTE_MASK_FRAGMENT;
        }
    }
    if (any(mask > vec3<f32>(0.0))) {
        colour = mix(colour, mask, 0.5);
    }

    if ((inset.show.x & SHOW_OUTCOMES) != 0u) {
        let id = textureLoad(reference_ids, texel, 0).x;
        if (id != 0u) {
            let code = outcomes[inset.show.z + id - 1u] & STATE_OUTCOME_BITS;
            // Thin diagonal stripes, so the map and the mask show between them.
            let stripe = (u32(in.clip.x) + u32(in.clip.y)) % 4u == 0u;
            if (code >= OUTCOME_EXCLUDED && stripe) {
                colour = outcome_colour(code).rgb;
            }
        }
    }
    return vec4<f32>(colour, 1.0);
}
