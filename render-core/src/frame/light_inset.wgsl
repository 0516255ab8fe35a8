// The light's view inset: the method's shadow map as grey (near the sun bright), the receiver
// mask in Bittner's colours (BVOL boxes blue, GEOM geometry green, FRAG texels red), and, where
// the reference map shows a caster the method culled, thin stripes in the colour of the stage
// that culled it (as the camera's `casters` overlay tints it: orange light frustum, yellow
// light occlusion, magenta mask or shadow volume). Keep in sync with frame/light_inset.rs.

@group(0) @binding(0) var shadow_map: texture_depth_2d;
@group(0) @binding(1) var reference_ids: texture_2d<u32>;
// Per instance, the outcome code in the low byte (frame/gpu_data.rs, `outcome_code`).
@group(0) @binding(2) var<storage, read> outcomes: array<u32>;
@group(0) @binding(3) var mask_raster: texture_2d<f32>;
@group(0) @binding(4) var<storage, read> mask_bits: array<u32>;
// x: SHOW_* bits; y: shadow texels per mask texel; z, w: unused.
@group(0) @binding(5) var<uniform> inset: vec4<u32>;

const SHOW_RASTER_MASK: u32 = 1u;
const SHOW_FRAGMENT_MASK: u32 = 2u;
const SHOW_OUTCOMES: u32 = 4u;
// Values the mask raster holds (culling/masks.wgsl).
const MARKED_BOX: f32 = 2.0;
const MARKED_GEOMETRY: f32 = 3.0;

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

// As the camera's `casters` tint (frame/camera.wgsl, `outcome_tint`).
fn stage_colour(code: u32) -> vec3<f32> {
    switch code {
        case 2u: { return vec3<f32>(0.6, 0.2, 0.9); }
        case 3u, 4u: { return vec3<f32>(1.0, 0.55, 0.05); }
        case 5u: { return vec3<f32>(0.95, 0.85, 0.1); }
        default: { return vec3<f32>(0.95, 0.1, 0.75); }
    }
}

@fragment
fn fs_light_view(in: VsOut) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(shadow_map));
    let texel = vec2<u32>(clamp(in.uv * size, vec2<f32>(0.0), size - 1.0));
    let depth = textureLoad(shadow_map, texel, 0);
    let near = pow(clamp(1.0 - depth, 0.0, 1.0), 2.0);
    let cleared = depth >= 1.0;
    var colour = select(vec3<f32>(0.05 + 0.95 * near), vec3<f32>(0.02, 0.02, 0.08), cleared);

    let m = texel / max(inset.y, 1u);
    var mask = vec3<f32>(0.0);
    if ((inset.x & SHOW_RASTER_MASK) != 0u) {
        let marked = textureLoad(mask_raster, m, 0).x;
        if (marked >= MARKED_GEOMETRY) {
            mask = vec3<f32>(0.1, 0.9, 0.2);
        } else if (marked >= MARKED_BOX) {
            mask = vec3<f32>(0.15, 0.35, 1.0);
        }
    }
    if ((inset.x & SHOW_FRAGMENT_MASK) != 0u) {
        let width = textureDimensions(mask_raster).x;
        if (bitcast<f32>(mask_bits[m.y * width + m.x]) > 0.0) {
            mask = vec3<f32>(1.0, 0.12, 0.1);
        }
    }
    if (any(mask > vec3<f32>(0.0))) {
        colour = mix(colour, mask, 0.5);
    }

    if ((inset.x & SHOW_OUTCOMES) != 0u) {
        let id = textureLoad(reference_ids, texel, 0).x;
        if (id != 0u) {
            let code = outcomes[id - 1u] & 0xffu;
            // Thin diagonal stripes, so the map and the mask show between them.
            let stripe = (u32(in.clip.x) + u32(in.clip.y)) % 4u == 0u;
            if (code >= 2u && stripe) {
                colour = stage_colour(code);
            }
        }
    }
    return vec4<f32>(colour, 1.0);
}
