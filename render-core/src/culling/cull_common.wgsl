// Culling parameters and per-instance bounds, shared by the caster tests (culling/cull.wgsl)
// and the bounding-volume mask (culling/masks.wgsl). Keep in sync with culling/gpu.rs.

struct CullParams {
    light_clip_from_world: mat4x4<f32>,
    // For DigitalRune's shadow volumes: light clip space back to world, and the camera.
    world_from_light_clip: mat4x4<f32>,
    camera_clip_from_world: mat4x4<f32>,
    // x: shadow map size in texels; y: mask size in texels; z: shadow texels per mask texel;
    // w: instance count.
    sizes: vec4<u32>,
    // x: method bits (METHOD_*); y: texels a mask built from whole receivers is widened by
    // (PCF radius, normal offset, rasterisation); z, w: unused.
    params: vec4<u32>,
    // x, y: the camera's view in pixels; z: the camera pyramid's base size; w: unused.
    camera: vec4<u32>,
    // x: how far a shadow volume starts before its caster (normalised light depth: the normal
    // offset and a texel); y, z, w: unused.
    volume: vec4<f32>,
}

const METHOD_OCCLUSION: u32 = 1u;
const METHOD_MASK: u32 = 2u;
const METHOD_DRAW_RECEIVERS: u32 = 4u;
const METHOD_ORACLE: u32 = 8u;
const METHOD_TEMPORAL: u32 = 16u;
// Receivers mark the mask with their geometry (GEOM), their boxes (BVOL), or by what was
// visible in the light's view last frame (GEOM+BVOL).
const METHOD_GEOM: u32 = 32u;
const METHOD_BVOL: u32 = 64u;
// The mask holds, per texel, the depth a caster must be nearer than to matter (FRAG).
const METHOD_FRAG: u32 = 128u;
// DigitalRune: the caster's shadow volume against the camera's frustum and depth, extruded to
// the far plane (conservative) or to the farthest depth behind it in the light's view
// (METHOD_PROGRESSIVE, which may be too short).
const METHOD_VOLUME: u32 = 256u;
const METHOD_PROGRESSIVE: u32 = 512u;
// Bittner 5.1: the map persists; the mask is the moving objects' old and new boxes, which are
// cleared and redrawn.
const METHOD_INCREMENTAL: u32 = 1024u;

// Per instance, in Bounds::flags.
const CULL_CASTER: u32 = 1u;
const CULL_RECEIVER: u32 = 2u;
const CULL_DYNAMIC: u32 = 4u;

// Per instance, in the state word: bits 0-7 the outcome code (frame/gpu_data.rs), then:
const STATE_LIGHT_VISIBLE: u32 = 256u;
const STATE_FIRST_PHASE: u32 = 512u;
// Bits 16-31: the progressive shadow volume's far end found last frame, in 1/65535 of the
// light's depth range (rounded up).
const STATE_EXTENT_SHIFT: u32 = 16u;

struct Bounds {
    // The world-space box and the CULL_* bits.
    min: vec3<f32>,
    flags: u32,
    max: vec3<f32>,
    padding: u32,
}

// The instance's box in light clip space: x, y in NDC, z in normalised depth.
struct LightBox {
    lo: vec3<f32>,
    hi: vec3<f32>,
}

fn light_box(b: Bounds, light_clip_from_world: mat4x4<f32>) -> LightBox {
    var out: LightBox;
    out.lo = vec3<f32>(1e30);
    out.hi = vec3<f32>(-1e30);
    for (var k = 0u; k < 8u; k++) {
        let corner = vec3<f32>(
            select(b.min.x, b.max.x, (k & 1u) != 0u),
            select(b.min.y, b.max.y, (k & 2u) != 0u),
            select(b.min.z, b.max.z, (k & 4u) != 0u),
        );
        let clip = light_clip_from_world * vec4<f32>(corner, 1.0);
        let ndc = clip.xyz / clip.w;
        out.lo = min(out.lo, ndc);
        out.hi = max(out.hi, ndc);
    }
    return out;
}

fn in_light_frustum(box: LightBox) -> bool {
    return all(box.hi >= vec3<f32>(-1.0, -1.0, 0.0)) && all(box.lo <= vec3<f32>(1.0));
}
