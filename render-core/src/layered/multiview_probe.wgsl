// Whether multiview reaches every layer (layered/probe.rs): a triangle over the whole target
// at depth 0.25 + 0.5 * view index, in a depth-only pass of two views.

@vertex
fn vs_probe(@builtin(vertex_index) i: u32, @builtin(view_index) view: u32) -> @builtin(position) vec4<f32> {
    let corners = array<vec2<f32>, 3>(vec2<f32>(-1.0, -1.0), vec2<f32>(3.0, -1.0), vec2<f32>(-1.0, 3.0));
    return vec4<f32>(corners[i], 0.25 + 0.5 * f32(view), 1.0);
}
