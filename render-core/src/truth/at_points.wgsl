// The technique's light reaching given surface points (truth/at_points.rs): the same light
// term the shading pass reads (technique/light.wgsl), at points the truth found by casting
// camera rays, not at the rasterised fragments. Groups 0-2 are the last frame's (frame
// uniforms and views, the technique's maps, measurement, which this pass never writes).
#import technique/light.wgsl

struct SurfacePoint {
    position: vec4<f32>,
    // The geometric normal on the camera's side.
    normal: vec4<f32>,
}

@group(3) @binding(0) var<storage, read> points: array<SurfacePoint>;
@group(3) @binding(1) var<storage, read_write> light_at: array<f32>;

const POINTS_PER_GROUP: u32 = 256u;

@compute @workgroup_size(256)
fn cs_light_at_points(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let i = gid.y * groups.x * POINTS_PER_GROUP + gid.x;
    if (i >= arrayLength(&points)) {
        return;
    }
    var light = 1.0;
    if (frame.params.y != 0u) {
        let p = points[i];
        light = light_reaching(p.position.xyz, p.normal.xyz, false).method;
    }
    light_at[i] = light;
}
