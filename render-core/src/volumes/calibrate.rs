//! Lloyd's V > R rule needs the cost of a volume vertex against that of a rasterised pixel
//! (3.2.1: "determined empirically by rendering a typical set of shadow volumes at different
//! resolutions"). Once per process and device: many stencil quads drawn into a 10 x 10 target
//! give the cost per vertex; a few drawn over a 1024 x 1024 one, less their vertices, the cost
//! per pixel. Their ratio, pixels per vertex, is how many gap pixels a new interval's extra
//! vertices are worth.

use std::sync::OnceLock;
use std::time::Instant;

use crate::gpu::{GpuContext, shader_module};

/// Quads of the small run and of the large one, each covering its whole target.
const SMALL: (u32, u32) = (10, 40_000);
const LARGE: (u32, u32) = (1024, 24);

/// Timed runs of each; the quickest counts.
const TIMED_RUNS: u32 = 5;

static PIXELS_PER_VERTEX: OnceLock<f32> = OnceLock::new();

/// The figure [`pixels_per_vertex`] measured in this process, if a frame has clamped
/// without a user's figure yet: benches print it, as it moves the fill between processes.
pub fn measured_pixels_per_vertex() -> Option<f32> {
    PIXELS_PER_VERTEX.get().copied()
}

/// Pixels a volume vertex costs as much as, on this process's first device (measured once);
/// between 0.01 and 1,000.
pub(super) fn pixels_per_vertex(ctx: &GpuContext, format: wgpu::TextureFormat) -> f32 {
    *PIXELS_PER_VERTEX.get_or_init(|| {
        let ratio = measure(ctx, format).unwrap_or(1.0).clamp(0.01, 1_000.0);
        log::info!("shadow volumes: a vertex costs as much as {ratio:.2} pixels (V > R rule)");
        ratio
    })
}

/// (seconds per vertex, seconds per pixel) as pixels per vertex; `None` when a run was too
/// quick to time.
fn measure(ctx: &GpuContext, format: wgpu::TextureFormat) -> Option<f32> {
    let device = &ctx.device;
    let module = shader_module(
        device,
        "Volumes::calibrate",
        "@vertex fn vs(@builtin(vertex_index) v: u32) -> @builtin(position) vec4<f32> {\n\
             let corners = array<vec2<f32>, 6>(vec2(-1.0, -1.0), vec2(1.0, -1.0), \
             vec2(1.0, 1.0), vec2(-1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0));\n\
             return vec4<f32>(corners[v % 6u], 0.5, 1.0);\n}\n"
            .to_owned(),
    );
    let face = wgpu::StencilFaceState {
        compare: wgpu::CompareFunction::Always,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op: wgpu::StencilOperation::Keep,
        pass_op: wgpu::StencilOperation::IncrementWrap,
    };
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("Volumes::calibrate"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: wgpu::StencilState {
                front: face,
                back: face,
                read_mask: 0xff,
                write_mask: 0xff,
            },
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    });
    let seconds = |(side, quads): (u32, u32)| -> Option<f64> {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("Volumes::calibrate"),
            size: wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let run = |quads: u32| -> Option<f64> {
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("Volumes::calibrate"),
            });
            {
                let mut pass = super::pipelines::depth_stencil_pass(
                    &mut encoder,
                    ("Volumes::calibrate", &view),
                    Some((0.0, 0)),
                    None,
                );
                pass.set_pipeline(&pipeline);
                pass.draw(0..quads * 6, 0..1);
            }
            let start = Instant::now();
            ctx.queue.submit([encoder.finish()]);
            ctx.wait_idle().ok()?;
            Some(start.elapsed().as_secs_f64())
        };
        // A first run compiles and warms up; the quickest of the timed runs is the cost,
        // the others having waited on something else (one timed run moved the ratio by a
        // third between processes, and with it the V > R rule's merges and the fill).
        run(1)?;
        (0..TIMED_RUNS).try_fold(f64::INFINITY, |best, _| Some(best.min(run(quads)?)))
    };
    let small = seconds(SMALL)?;
    let large = seconds(LARGE)?;
    let per_vertex = small / f64::from(SMALL.1 * 6);
    let pixels = f64::from(LARGE.1) * f64::from(LARGE.0 * LARGE.0);
    let per_pixel = (large - per_vertex * f64::from(LARGE.1 * 6)) / pixels;
    (per_vertex > 0.0 && per_pixel > 0.0).then(|| (per_vertex / per_pixel) as f32)
}
