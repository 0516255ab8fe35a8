// The culled draws (layered/cull.wgsl's records): a triangle per three vertices, its vertices
// fetched from the scene's buffer, for each path: a pass per view (`vs_culled`), a multiview
// group (`vs_culled_multiview`), or an atlas page (`vs_culled_atlas`, clip distances at the
// tile's edges, composed with `enable clip_distances;` first).
#import view/common.wgsl
#import layered/load.wgsl

// The view of the pass (the group's first for multiview).
@group(1) @binding(0) var<uniform> pass_view: ShadowView;
@group(2) @binding(0) var<storage, read> records: array<vec4<u32>>;
@group(2) @binding(1) var<storage, read> vertices: array<f32>;
// x: the atlas page's side in texels.
@group(2) @binding(2) var<uniform> page: vec4<f32>;

struct Corner {
    position: vec3<f32>,
    instance: u32,
    view: u32,
}

fn corner(vertex_index: u32) -> Corner {
    let record = records[vertex_index / 3u];
    let i = record[vertex_index % 3u];
    var out: Corner;
    out.position = vec3<f32>(vertices[i * 6u], vertices[i * 6u + 1u], vertices[i * 6u + 2u]);
    out.instance = record.w & 0xffffffu;
    out.view = record.w >> 24u;
    return out;
}

struct CulledOut {
    @invariant @builtin(position) clip: vec4<f32>,
}

@vertex
fn vs_culled(@builtin(vertex_index) vertex_index: u32) -> CulledOut {
    let c = corner(vertex_index);
    var out: CulledOut;
    out.clip = loaded(pass_view, shadow_clip_position(pass_view, c.instance, c.position));
    return out;
}
