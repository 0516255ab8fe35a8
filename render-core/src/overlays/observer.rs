//! The observer camera's picture of a frozen view (three.js's CSM helper, MJP's "freeze
//! cascades"): the frozen camera's frustum (white), the depths where its cascades meet (each
//! cascade's colour) and each shadow view's light box (its colour), as lines drawn over the
//! scene seen from the observer (`observer_lines.wgsl`).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};

use crate::geom::{BOX_EDGES, Camera};
use crate::gpu::{bind_group_layout, buffer_entry, pipeline_layout, shader_module, uniform};
use crate::palette;
use crate::shadow_view::{DepthMeasure, ShadowView};
use crate::view::targets::{COLOR_FORMAT, ViewTargets};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct LineVertex {
    position: [f32; 4],
    colour: [f32; 4],
}

/// The frozen view's frustum and the shadow views' boxes as line segments (pairs of points),
/// each with its colour.
pub fn observer_segments(
    frozen: &Camera,
    aspect: f32,
    far_m: f32,
    views: &[ShadowView],
) -> Vec<([Vec3; 2], [f32; 3])> {
    let aspect = f64::from(if aspect.is_finite() && aspect > 0.0 {
        aspect
    } else {
        1.0
    });
    let near = f64::from(frozen.near_m);
    let far = f64::from(far_m.max(frozen.near_m * 2.0));
    let mut out = Vec::new();
    let hexahedron = |corners: [Vec3; 8], colour: [f32; 3], out: &mut Vec<_>| {
        for (a, b) in BOX_EDGES {
            out.push(([corners[a], corners[b]], colour));
        }
    };
    let corners = frozen
        .frustum_corners_world(aspect, near, far)
        .map(glam::DVec3::as_vec3);
    hexahedron(corners, [1.0, 1.0, 1.0], &mut out);
    for (i, view) in views.iter().enumerate() {
        let colour = palette::VIEWS[i % palette::VIEWS.len()].rgb;
        // Where the cascade's depths end, across the frozen frustum; a distance from the eye
        // where it meets the frustum's edges.
        let end = f64::from(view.shades_depth_m[1])
            * match view.shades_by {
                DepthMeasure::ViewDepth => 1.0,
                DepthMeasure::EyeDistance => frozen.corner_cosine(aspect),
            };
        if end.is_finite() && end > near && end < far {
            let c = frozen
                .frustum_corners_world(aspect, end, end)
                .map(glam::DVec3::as_vec3);
            for (a, b) in [(0, 1), (1, 3), (3, 2), (2, 0)] {
                out.push(([c[a], c[b]], colour));
            }
        }
        let world_from_clip = view.light.light_clip_from_world.inverse();
        let box_corners: [Vec3; 8] = std::array::from_fn(|k| {
            let ndc = Vec4::new(
                if k & 1 == 0 { -1.0 } else { 1.0 },
                if k & 2 == 0 { -1.0 } else { 1.0 },
                if k & 4 == 0 { 0.0 } else { 1.0 },
                1.0,
            );
            let w = world_from_clip * ndc;
            w.truncate() / w.w
        });
        if box_corners.iter().all(|c| c.is_finite()) {
            hexahedron(box_corners, colour, &mut out);
        }
    }
    out
}

/// The lines' pipeline, uniforms and vertices; long-lived, the vertices grown as needed.
pub struct ObserverLines {
    pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    group: wgpu::BindGroup,
    vertices: wgpu::Buffer,
}

/// Vertices the first buffer holds (a frustum, and 8 views' boxes and ends).
const FIRST_VERTICES: u64 = 512;

fn vertex_buffer(device: &wgpu::Device, vertices: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("ObserverLines::vertices"),
        size: vertices * std::mem::size_of::<LineVertex>() as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl ObserverLines {
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = bind_group_layout(
            device,
            "ObserverLines::layout",
            wgpu::ShaderStages::VERTEX,
            &[uniform()],
        );
        let module = shader_module(device, "ObserverLines::shader", shader_source());
        let pipeline_layout = pipeline_layout(device, "ObserverLines::pipeline_layout", &[&layout]);
        let attributes = wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("ObserverLines::pipeline"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_line"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<LineVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::LineList,
                ..wgpu::PrimitiveState::default()
            },
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_line"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(COLOR_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ObserverLines::uniforms"),
            size: std::mem::size_of::<Mat4>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ObserverLines::group"),
            layout: &layout,
            entries: &[buffer_entry(0, &uniforms)],
        });
        Self {
            pipeline,
            uniforms,
            group,
            vertices: vertex_buffer(device, FIRST_VERTICES),
        }
    }

    /// Draws `segments` over the colour target, seen through `clip_from_world`.
    pub fn draw(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        targets: &ViewTargets,
        clip_from_world: Mat4,
        segments: &[([Vec3; 2], [f32; 3])],
    ) {
        if segments.is_empty() {
            return;
        }
        let vertices: Vec<LineVertex> = segments
            .iter()
            .flat_map(|(ends, rgb)| {
                ends.map(|p| LineVertex {
                    position: p.extend(1.0).to_array(),
                    colour: [rgb[0], rgb[1], rgb[2], 1.0],
                })
            })
            .collect();
        let bytes: &[u8] = bytemuck::cast_slice(&vertices);
        if bytes.len() as u64 > self.vertices.size() {
            self.vertices = vertex_buffer(device, (vertices.len() as u64).next_power_of_two());
        }
        queue.write_buffer(&self.vertices, 0, bytes);
        queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::cast_slice(&clip_from_world.to_cols_array()),
        );
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("ObserverLines::draw"),
            color_attachments: &[Some(crate::gpu::color_attachment(
                &targets.color_view,
                wgpu::LoadOp::Load,
            ))],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..bytes.len() as u64));
        pass.draw(0..vertices.len() as u32, 0..1);
    }
}

/// The lines' shader.
pub(crate) fn shader_source() -> String {
    crate::shaders::compose("overlays/observer_lines.wgsl", &[])
}
