//! The camera's passes: a depth + object-id prepass, then shading with the shadow technique's
//! light term (`frame/camera.wgsl`). Long-lived pipelines, built for one technique's light
//! term and layout.

use crate::gpu::{
    FrameTimer, color_attachment, depth_attachment, pass_label, pipeline_layout, shader_module,
};
use crate::scene_gpu::{DrawList, SceneGpu};
use crate::technique::compose_with_light_term;
use crate::view::camera_pipeline;
use crate::view::targets::{
    COLOR_FORMAT, ID_FORMAT, SHADOW_FACTOR_FORMAT, SURFACE_FORMAT, ViewTargets,
};

/// Linear sky colour behind the scene.
const SKY: wgpu::Color = wgpu::Color {
    r: 0.42,
    g: 0.58,
    b: 0.80,
    a: 1.0,
};

/// The camera passes' shader with a technique's light term, the file `light_wgsl`. Without
/// forced early depth tests the shading pass cannot measure, so the attribute is dropped there
/// (and measurement is switched off).
pub(crate) fn shader_source(light_wgsl: &str, early_depth_test: bool) -> String {
    let source = compose_with_light_term("frame/camera.wgsl", light_wgsl);
    if early_depth_test {
        source
    } else {
        source.replace("@early_depth_test(force)", "")
    }
}

/// What the shading pass binds besides group 0.
pub(super) struct ShadingGroups<'a> {
    pub frame: &'a wgpu::BindGroup,
    /// The technique's light term (group 1).
    pub light: &'a wgpu::BindGroup,
    /// Measurement and outcomes (group 2, `metrics/measure.wgsl`).
    pub measure: &'a wgpu::BindGroup,
}

pub(super) struct CameraPasses {
    prepass: wgpu::RenderPipeline,
    shade: wgpu::RenderPipeline,
}

impl CameraPasses {
    /// `layouts`: group 0 of scene passes, the technique's light group, the measure group.
    pub fn new(
        device: &wgpu::Device,
        light_wgsl: &str,
        layouts: [&wgpu::BindGroupLayout; 3],
        early_depth_test: bool,
    ) -> Self {
        let module = shader_module(
            device,
            "Frame::camera_shader",
            shader_source(light_wgsl, early_depth_test),
        );
        let prepass_layout = pipeline_layout(device, "Frame::prepass_layout", &layouts[..1]);
        let shade_layout = pipeline_layout(device, "Frame::shade_layout", &layouts);
        Self {
            prepass: camera_pipeline(
                device,
                "Frame::prepass_pipeline",
                &prepass_layout,
                &module,
                "fs_prepass",
                &[
                    Some(ID_FORMAT.into()),
                    Some(SURFACE_FORMAT.into()),
                    Some(SURFACE_FORMAT.into()),
                ],
                (true, wgpu::CompareFunction::Greater),
            ),
            shade: camera_pipeline(
                device,
                "Frame::shade_pipeline",
                &shade_layout,
                &module,
                "fs_shade",
                &[Some(COLOR_FORMAT.into()), Some(SHADOW_FACTOR_FORMAT.into())],
                (false, wgpu::CompareFunction::Equal),
            ),
        }
    }

    /// Reversed depth and object ids of what the camera sees.
    pub fn draw_prepass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &FrameTimer,
        targets: &ViewTargets,
        (scene_gpu, draws, indirect_first_instance): (&SceneGpu, &DrawList, bool),
        frame_group: &wgpu::BindGroup,
    ) {
        let query = timer.begin_pass(pass_label::CAMERA_PREPASS, encoder);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("Frame::draw_camera_prepass"),
                color_attachments: &[
                    Some(color_attachment(
                        &targets.ids_view,
                        wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    )),
                    Some(color_attachment(
                        &targets.positions_view,
                        wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    )),
                    Some(color_attachment(
                        &targets.normals_view,
                        wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    )),
                ],
                depth_stencil_attachment: Some(depth_attachment(&targets.depth_view, Some(0.0))),
                timestamp_writes: query
                    .as_ref()
                    .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.prepass);
            pass.set_bind_group(0, frame_group, &[]);
            draws.draw(&mut pass, scene_gpu, indirect_first_instance);
        }
        timer.end_pass(encoder, query);
    }

    /// Depth-equal shading of the visible surfaces (early depth test forced): colour, and the
    /// method's and the reference's light per pixel.
    pub fn draw_shading(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &FrameTimer,
        targets: &ViewTargets,
        (scene_gpu, draws, indirect_first_instance): (&SceneGpu, &DrawList, bool),
        groups: &ShadingGroups<'_>,
    ) {
        let query = timer.begin_pass(pass_label::SHADING, encoder);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("Frame::draw_shading"),
                color_attachments: &[
                    Some(color_attachment(
                        &targets.color_view,
                        wgpu::LoadOp::Clear(SKY),
                    )),
                    Some(color_attachment(
                        &targets.shadow_view,
                        wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                    )),
                ],
                depth_stencil_attachment: Some(depth_attachment(&targets.depth_view, None)),
                timestamp_writes: query
                    .as_ref()
                    .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.shade);
            pass.set_bind_group(0, groups.frame, &[]);
            pass.set_bind_group(1, groups.light, &[]);
            pass.set_bind_group(2, groups.measure, &[]);
            draws.draw(&mut pass, scene_gpu, indirect_first_instance);
        }
        timer.end_pass(encoder, query);
    }
}
