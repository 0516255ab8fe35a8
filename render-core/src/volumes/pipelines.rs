//! The volume technique's shaders, uniforms, render pipelines and dispatch sizes.

use bytemuck::{Pod, Zeroable};

use crate::gpu::{pipeline_layout, shader_module};
use crate::scene_gpu::VERTEX_LAYOUT;

/// The volume passes' shaders: (label, WGSL), as they are built.
#[cfg(test)]
pub(crate) fn shader_sources() -> Vec<(String, String)> {
    let mut shaders: Vec<(String, String)> = vec![
        (
            "volumes/find.wgsl".to_owned(),
            shader_source("volumes/find.wgsl"),
        ),
        ("volumes/draw.wgsl".to_owned(), draw_shader_source(true)),
        (
            "volumes/draw.wgsl (no clip distances)".to_owned(),
            draw_shader_source(false),
        ),
    ];
    shaders.push((
        "volumes/fill_heat.wgsl".to_owned(),
        super::fill::heat_shader_source(),
    ));
    shaders
}

/// A volume pass's shader, with culling's codes and the palette.
pub(super) fn shader_source(path: &str) -> String {
    let codes = crate::culling::codes::wgsl();
    let palette = crate::palette::wgsl();
    crate::shaders::compose(
        path,
        &[
            (crate::culling::codes::WGSL_PATH, codes.as_str()),
            (crate::palette::WGSL_PATH, palette.as_str()),
        ],
    )
}

/// The volumes' draw shader; where the adapter has `CLIP_DISTANCES` (`clip_distances`), each
/// interval is clipped to the strips of the picture its receivers lie in
/// (`volumes/strips_clipped.wgsl`), else drawn across the picture (`strips_whole.wgsl`).
pub(super) fn draw_shader_source(clip_distances: bool) -> String {
    let codes = crate::culling::codes::wgsl();
    let palette = crate::palette::wgsl();
    let strips = if clip_distances {
        "#import volumes/strips_clipped.wgsl\n"
    } else {
        "#import volumes/strips_whole.wgsl\n"
    };
    let source = crate::shaders::compose(
        "volumes/draw.wgsl",
        &[
            (crate::culling::codes::WGSL_PATH, codes.as_str()),
            (crate::palette::WGSL_PATH, palette.as_str()),
            ("volumes/strips.wgsl", strips),
        ],
    );
    if clip_distances {
        format!("enable clip_distances;\n{source}")
    } else {
        source
    }
}

/// `VolumeFrame` in `volumes/common.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(super) struct VolumeFrameGpu {
    pub to_light: [f32; 4],
    pub counts: [u32; 4],
    pub options: [u32; 4],
    pub right: [f32; 4],
    pub up: [f32; 4],
    pub travel: [f32; 4],
    pub cell: [f32; 4],
    pub steps: [u32; 4],
    pub near_lo: [f32; 4],
    pub near_hi: [f32; 4],
    pub slicing: [f32; 4],
    pub grid: [u32; 4],
    pub point: [f32; 4],
    pub near_planes: [[f32; 4]; 5],
    /// Written apart when the volumes are drawn (`picture_bytes`).
    pub picture: [f32; 4],
}

impl VolumeFrameGpu {
    /// Where `picture` lies in the buffer, and its bytes for a picture of `size`.
    pub fn picture_bytes(size: (u32, u32)) -> (u64, [f32; 4]) {
        (
            std::mem::offset_of!(Self, picture) as u64,
            [size.0.max(1) as f32, size.1.max(1) as f32, 0.0, 0.0],
        )
    }
}

/// The most intervals a caster's volume is drawn in (`MAX_INTERVALS` in
/// `volumes/common.wgsl`).
pub(super) const MAX_INTERVALS: u32 = 4;
/// Discrete clamping's most slices (`MAX_SLICES` in `volumes/common.wgsl`).
pub(super) const MAX_SLICES: u32 = crate::shadow_view::VolumeSettings::MAX_SLICES;

/// The most cells of the grid of visible receiver points in the light's view, per slice.
pub(super) const RECEIVER_CELLS: u32 = 512 * 512;
/// The most casters a frame can leave to workgroups of their own (`BIG_CASTERS` in
/// `volumes/big_casters.wgsl`); how many it does is the adapter's `StepBudget::big_casters`.
pub(super) const BIG_CASTERS: u32 = 1024;
/// Lanes of the cull's workgroup, one per caster (`CULL_LANES` in `volumes/find.wgsl`).
pub(super) const CULL_LANES: u32 = 32;
/// Lanes per workgroup of a big caster (`BIG_LANES` in `volumes/big_casters.wgsl`).
pub(super) const BIG_LANES: u32 = 256;
/// The bytes of their list: a count, the casters, and what each one's lanes merged
/// (`BIG_WORDS`: three words per slice and one more).
pub(super) const BIG_CASTERS_BYTES: u64 = BIG_DISPATCH_OFFSET + BIG_DISPATCH_BYTES;
/// Where the big casters' dispatch sizes follow the list (`BIG_DISPATCH` in
/// `volumes/big_casters.wgsl`), and their bytes: two indirect dispatches of 16 bytes.
pub(super) const BIG_DISPATCH_OFFSET: u64 =
    4 * (1 + BIG_CASTERS as u64 * (2 + 3 * MAX_SLICES as u64));
pub(super) const BIG_DISPATCH_BYTES: u64 = 32;
/// The depth bins of each grid cell (`DEPTH_BINS` in `volumes/grid.wgsl`).
pub(super) const DEPTH_BINS: u32 = 32;

/// Work items per workgroup of the silhouette passes.
pub(super) const WORKGROUP: u32 = 64;
/// Workgroups per dispatch row.
pub(super) const ROW_GROUPS: u32 = 65_535;

/// The camera's visible surface into the depth-stencil target: its vertex stage, no colour.
pub(super) fn depth_pipeline(
    device: &wgpu::Device,
    frame_layout: &wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let module = shader_module(
        device,
        "Volumes::depth",
        crate::shaders::compose("view/camera_vertex.wgsl", &[]),
    );
    let layout = pipeline_layout(device, "Volumes::depth_layout", &[frame_layout]);
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("Volumes::depth"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[Some(VERTEX_LAYOUT)],
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}

/// What a pipeline over the volume faces does.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum VolumePass {
    /// Both sides, nothing written but the stencil, counted as the draw's [`Counting`].
    Stencil,
    /// The depth test off, every fragment counted by `fs_fill` (`fill.rs`).
    Fill,
    /// In front of the visible surface, translucent over the colour target (`fs_volume`,
    /// the `volumes` overlay).
    Overlay,
}

/// Where a volume's faces count in the stencil.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Counting {
    /// Behind the visible surface a back face counts +1 and a front face -1 (caps drawn).
    ZFail,
    /// In front of it a front face counts +1 and a back face -1.
    ZPass,
}

/// Which faces of the volumes a draw holds.
#[derive(Clone, Copy, PartialEq)]
enum Faces {
    /// The silhouette quads.
    Quads,
    /// The casters' own triangles where an interval starts at them, as the camera sees them
    /// (`Side`): clipped at the near plane as the camera's passes clip them (a clamped
    /// triangle that crosses the near plane interpolates other depths there).
    NearCaps(Side),
    /// The same of casters that reach past the far plane: clamped, or the far plane would
    /// clip them and not the rest of their volume.
    PastFarCaps(Side),
    /// The caps moved along the light, where intervals start further on and where they end
    /// (the lit triangles, or fans over the silhouette, `fan_capped` in
    /// `volumes/common.wgsl`): no surface lies under them, so no bias (it would push a cap
    /// just above a receiver seen at a grazing angle behind it).
    MovedCaps,
}

/// Which side of a cap at its caster the camera sees: a draw culls the other.
#[derive(Clone, Copy, PartialEq)]
enum Side {
    /// Its outside, where its caster's triangle may be the visible surface: pushed back by
    /// [`CAP_BIAS`] so a lit surface it lies on counts it behind itself, outside the volume,
    /// whatever the rounding.
    Outside,
    /// Its inside (the camera inside the caster, or the back of an open caster's triangle):
    /// the camera culls that triangle there, so no surface lies on the cap and no bias. The
    /// bias, twice the depth slope, would push a cap seen edge-on from inside a wall behind
    /// the floor in front of the wall, a band of false shadow along its foot.
    Inside,
}

impl Faces {
    /// Pushed back by [`CAP_BIAS`].
    fn biased(self) -> bool {
        matches!(
            self,
            Self::NearCaps(Side::Outside) | Self::PastFarCaps(Side::Outside)
        )
    }

    /// The faces a draw of them culls: a cap's other side.
    fn culled(self) -> Option<wgpu::Face> {
        match self {
            Self::NearCaps(Side::Outside) | Self::PastFarCaps(Side::Outside) => {
                Some(wgpu::Face::Back)
            }
            Self::NearCaps(Side::Inside) | Self::PastFarCaps(Side::Inside) => {
                Some(wgpu::Face::Front)
            }
            Self::Quads | Self::MovedCaps => None,
        }
    }

    fn near_caps(self) -> bool {
        matches!(self, Self::NearCaps(_))
    }
}

/// One draw of the volume faces: its vertex entry, how it counts, its faces and which of
/// the indirect arguments it draws (16 bytes each, `volumes/find.wgsl` `draws`: z-fail
/// quads, caps at the casters, moved caps and fan caps, then z-pass). All but near caps are
/// depth clamped where the adapter can, so nothing is clipped at the far plane. Caps at the
/// casters are drawn twice, each side by its own draw.
struct VolumeDraw {
    entry: &'static str,
    counting: Counting,
    faces: Faces,
    args: u64,
}

const DRAWS: [VolumeDraw; 14] = [
    VolumeDraw::new("vs_quad", Counting::ZFail, Faces::Quads, 0),
    VolumeDraw::new(
        "vs_near_cap",
        Counting::ZFail,
        Faces::NearCaps(Side::Outside),
        1,
    ),
    VolumeDraw::new(
        "vs_near_cap",
        Counting::ZFail,
        Faces::NearCaps(Side::Inside),
        1,
    ),
    VolumeDraw::new(
        "vs_past_far_cap",
        Counting::ZFail,
        Faces::PastFarCaps(Side::Outside),
        1,
    ),
    VolumeDraw::new(
        "vs_past_far_cap",
        Counting::ZFail,
        Faces::PastFarCaps(Side::Inside),
        1,
    ),
    VolumeDraw::new("vs_moved_cap", Counting::ZFail, Faces::MovedCaps, 2),
    VolumeDraw::new("vs_fan_cap", Counting::ZFail, Faces::MovedCaps, 3),
    VolumeDraw::new("vs_quad_pass", Counting::ZPass, Faces::Quads, 4),
    VolumeDraw::new(
        "vs_near_cap_pass",
        Counting::ZPass,
        Faces::NearCaps(Side::Outside),
        5,
    ),
    VolumeDraw::new(
        "vs_near_cap_pass",
        Counting::ZPass,
        Faces::NearCaps(Side::Inside),
        5,
    ),
    VolumeDraw::new(
        "vs_past_far_cap_pass",
        Counting::ZPass,
        Faces::PastFarCaps(Side::Outside),
        5,
    ),
    VolumeDraw::new(
        "vs_past_far_cap_pass",
        Counting::ZPass,
        Faces::PastFarCaps(Side::Inside),
        5,
    ),
    VolumeDraw::new("vs_moved_cap_pass", Counting::ZPass, Faces::MovedCaps, 6),
    VolumeDraw::new("vs_fan_cap_pass", Counting::ZPass, Faces::MovedCaps, 7),
];

impl VolumeDraw {
    const fn new(entry: &'static str, counting: Counting, faces: Faces, args: u64) -> Self {
        Self {
            entry,
            counting,
            faces,
            args,
        }
    }
}

/// Caps' depth bias: towards the far plane (reversed depth: negative), a few units and twice
/// the triangle's depth slope, so that a cap on a lit face seen edge-on still lies behind it.
const CAP_BIAS: wgpu::DepthBiasState = wgpu::DepthBiasState {
    constant: -4,
    slope_scale: -2.0,
    clamp: 0.0,
};

/// The pipelines of one kind from one module, one per draw of the volume faces.
struct VolumePipelines([wgpu::RenderPipeline; DRAWS.len()]);

impl VolumePipelines {
    /// `depth_clamped`: the adapter clamps depth (`DEPTH_CLIP_CONTROL`); `cut`: `module` cuts
    /// each interval to its strips (`draw_shader_source`), so the stencil pass keeps a
    /// fragment only where its piece is whole (`fs_stencil`).
    pub fn new(
        device: &wgpu::Device,
        (layout, module): (&wgpu::PipelineLayout, &wgpu::ShaderModule),
        (format, depth_clamped, cut): (wgpu::TextureFormat, bool, bool),
        kind: VolumePass,
    ) -> Self {
        Self(DRAWS.each_ref().map(|draw| {
            volume_pipeline(
                device,
                (layout, module, draw.entry),
                (format, depth_clamped && !draw.faces.near_caps(), cut),
                (kind, draw.counting, draw.faces),
            )
        }))
    }

    /// Draws every record of `draws` (the indirect arguments).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, draws: &wgpu::Buffer) {
        for (draw, pipeline) in DRAWS.iter().zip(&self.0) {
            pass.set_pipeline(pipeline);
            pass.draw_indirect(draws, draw.args * 16);
        }
    }
}

/// The draw shader's two modules: volumes across the whole picture, and, where the adapter
/// has `CLIP_DISTANCES`, cut to the strips of discrete clamping (`draw_shader_source`).
pub(super) struct DrawModules {
    whole: wgpu::ShaderModule,
    cut: Option<wgpu::ShaderModule>,
}

impl DrawModules {
    pub fn new(device: &wgpu::Device, clip_distances: bool) -> Self {
        let module = |cut| shader_module(device, "Volumes::draw", draw_shader_source(cut));
        Self {
            whole: module(false),
            cut: clip_distances.then(|| module(true)),
        }
    }
}

/// The pipelines of one kind from each draw module. Only frames cut into more than one
/// strip draw with the cut ones: the clip distances and the fragment stage that tests them
/// cost every triangle and fragment of every volume, where one strip cuts nothing.
pub(super) struct StripPipelines {
    whole: VolumePipelines,
    cut: Option<VolumePipelines>,
}

impl StripPipelines {
    pub fn new(
        device: &wgpu::Device,
        (layout, modules): (&wgpu::PipelineLayout, &DrawModules),
        (format, depth_clamped): (wgpu::TextureFormat, bool),
        kind: VolumePass,
    ) -> Self {
        let pipelines = |module, cut| {
            VolumePipelines::new(device, (layout, module), (format, depth_clamped, cut), kind)
        };
        Self {
            whole: pipelines(&modules.whole, false),
            cut: modules.cut.as_ref().map(|module| pipelines(module, true)),
        }
    }

    /// Draws every record of `draws`, cut to their strips where `cut` and the adapter can.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, draws: &wgpu::Buffer, cut: bool) {
        match &self.cut {
            Some(pipelines) if cut => pipelines.draw(pass, draws),
            _ => self.whole.draw(pass, draws),
        }
    }
}

/// A pipeline drawing the volume faces from vertex entry `entry` of `module`.
fn volume_pipeline(
    device: &wgpu::Device,
    (layout, module, entry): (&wgpu::PipelineLayout, &wgpu::ShaderModule, &str),
    (format, unclipped_depth, cut): (wgpu::TextureFormat, bool, bool),
    (kind, counting, faces): (VolumePass, Counting, Faces),
) -> wgpu::RenderPipeline {
    use wgpu::StencilOperation::{DecrementWrap, IncrementWrap, Keep};
    // (depth fail, depth pass) operations of the front and the back faces.
    let face = |(depth_fail_op, pass_op)| wgpu::StencilFaceState {
        compare: wgpu::CompareFunction::Always,
        fail_op: Keep,
        depth_fail_op,
        pass_op,
    };
    let (front, back) = match counting {
        Counting::ZFail => ((DecrementWrap, Keep), (IncrementWrap, Keep)),
        Counting::ZPass => ((Keep, IncrementWrap), (Keep, DecrementWrap)),
    };
    let (depth_compare, stencil, fragment) = match kind {
        VolumePass::Stencil => (
            wgpu::CompareFunction::Greater,
            wgpu::StencilState {
                front: face(front),
                back: face(back),
                read_mask: 0xff,
                write_mask: 0xff,
            },
            cut.then_some(wgpu::FragmentState {
                module,
                entry_point: Some("fs_stencil"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[],
            }),
        ),
        VolumePass::Fill => (
            wgpu::CompareFunction::Always,
            wgpu::StencilState::default(),
            Some(wgpu::FragmentState {
                module,
                entry_point: Some(match counting {
                    Counting::ZFail => "fs_fill",
                    Counting::ZPass => "fs_fill_pass",
                }),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[],
            }),
        ),
        VolumePass::Overlay => (
            wgpu::CompareFunction::Greater,
            wgpu::StencilState::default(),
            Some(wgpu::FragmentState {
                module,
                entry_point: Some("fs_volume"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &OVERLAY_TARGET,
            }),
        ),
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(entry),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: faces.culled(),
            unclipped_depth,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(false),
            depth_compare: Some(depth_compare),
            stencil,
            bias: if faces.biased() {
                CAP_BIAS
            } else {
                wgpu::DepthBiasState::default()
            },
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment,
        multiview_mask: None,
        cache: None,
    })
}

/// Workgroups for `items` work items, in rows of [`ROW_GROUPS`].
pub(super) fn dispatch_size(items: u32) -> (u32, u32) {
    group_rows(items.div_ceil(WORKGROUP))
}

/// `groups` workgroups in rows of [`ROW_GROUPS`].
pub(super) fn group_rows(groups: u32) -> (u32, u32) {
    if groups <= ROW_GROUPS {
        (groups, 1)
    } else {
        (ROW_GROUPS, groups.div_ceil(ROW_GROUPS))
    }
}

/// The `volumes` overlay's blend over the view.
const OVERLAY_TARGET: [Option<wgpu::ColorTargetState>; 1] = [Some(wgpu::ColorTargetState {
    format: crate::view::targets::COLOR_FORMAT,
    blend: Some(wgpu::BlendState::ALPHA_BLENDING),
    write_mask: wgpu::ColorWrites::ALL,
})];

/// A pass on the volumes' depth-stencil target: both cleared to `clear` (depth, stencil) or
/// kept, both stored.
pub(super) fn depth_stencil_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    (label, view): (&str, &wgpu::TextureView),
    clear: Option<(f32, u32)>,
    query: Option<&wgpu_profiler::GpuProfilerQuery>,
) -> wgpu::RenderPass<'e> {
    fn ops<T>(load: wgpu::LoadOp<T>) -> wgpu::Operations<T> {
        wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        }
    }
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(ops(
                clear.map_or(wgpu::LoadOp::Load, |c| wgpu::LoadOp::Clear(c.0))
            )),
            stencil_ops: Some(ops(
                clear.map_or(wgpu::LoadOp::Load, |c| wgpu::LoadOp::Clear(c.1))
            )),
        }),
        timestamp_writes: query
            .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// A pass that tests against the volumes' depth-stencil target without writing it: the fill
/// count (no colour) and the `volumes` overlay (over the colour target).
pub(super) fn read_only_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    color: Option<&wgpu::TextureView>,
    depth_stencil: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    let color = color.map(|view| wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Load,
            store: wgpu::StoreOp::Store,
        },
    });
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: if color.is_some() {
            std::slice::from_ref(&color)
        } else {
            &[]
        },
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth_stencil,
            depth_ops: None,
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
