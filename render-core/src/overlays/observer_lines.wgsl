// The observer camera's lines (overlays/observer.rs): the frozen view's frustum and slices and
// each shadow view's light box, in world space, drawn over the picture from the observer.

struct Lines {
    clip_from_world: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> lines: Lines;

struct LineVertex {
    @location(0) position: vec4<f32>,
    @location(1) colour: vec4<f32>,
}

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
}

@vertex
fn vs_line(v: LineVertex) -> LineOut {
    var out: LineOut;
    out.clip = lines.clip_from_world * vec4<f32>(v.position.xyz, 1.0);
    out.colour = v.colour;
    return out;
}

@fragment
fn fs_line(in: LineOut) -> @location(0) vec4<f32> {
    return in.colour;
}
