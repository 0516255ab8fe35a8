//! Headless frames: render, wait for the GPU, and read the targets back.

use std::time::{Duration, Instant};

use super::{FrameInput, FrameRenderer, FrameReport, SceneGpu, ViewTargets};
use crate::gpu::{GpuContext, GpuError, read_texture};
use crate::scene::Scene;

/// The camera targets of one frame on the CPU, row-major from the top-left pixel.
#[derive(Clone, Debug)]
pub struct FrameCapture {
    pub width: u32,
    pub height: u32,
    /// sRGB-encoded colour, as a screenshot saves it.
    pub color: image::RgbaImage,
    /// Instance index + 1 per pixel, 0 for sky.
    pub ids: Vec<u32>,
    /// Reversed depth: 1 at the near plane, 0 at the far plane and for sky.
    pub depth: Vec<f32>,
    /// Fraction of shadow taps that see the sun in the method's map, 0..=255.
    pub shadow: Vec<u8>,
    /// The same from the reference map (equal to `shadow` unless the frame measured).
    pub reference_shadow: Vec<u8>,
}

impl FrameCapture {
    pub fn read(ctx: &GpuContext, targets: &ViewTargets) -> Result<Self, GpuError> {
        let color = read_texture(ctx, &targets.color, wgpu::TextureAspect::All)?
            .into_rgba_image()
            .ok_or_else(|| GpuError::Readback {
                what: "colour target".into(),
                reason: "not 4 bytes per texel".into(),
            })?;
        let shadow = read_texture(ctx, &targets.shadow, wgpu::TextureAspect::All)?.bytes;
        Ok(Self {
            width: targets.width,
            height: targets.height,
            color,
            ids: read_texture(ctx, &targets.ids, wgpu::TextureAspect::All)?.to_u32(),
            depth: read_texture(ctx, &targets.depth, wgpu::TextureAspect::DepthOnly)?.to_f32(),
            shadow: shadow.iter().step_by(2).copied().collect(),
            reference_shadow: shadow.iter().skip(1).step_by(2).copied().collect(),
        })
    }
}

impl FrameRenderer {
    /// The report of a frame that `fault` stopped before it drew.
    pub(super) fn faulted(&self, fault: crate::gpu::GpuFault) -> FrameReport {
        log::debug!("frame {}: {fault}", self.frame_index);
        FrameReport {
            frame_index: self.frame_index,
            fault: Some(fault),
            ..FrameReport::default()
        }
    }

    /// Renders `input`, waits for the GPU, and returns the report with this frame's GPU times,
    /// visible counts and measurements. Readbacks are mapped by whichever thread polls the
    /// device, so it keeps polling until this frame's results are in (ten seconds at most).
    pub fn render_and_wait(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        scene_gpu: &SceneGpu,
        input: &FrameInput<'_>,
    ) -> Result<FrameReport, GpuError> {
        let mut report = self.render(ctx, scene, scene_gpu, input);
        if let Some(fault) = report.fault {
            return Err(fault.into());
        }
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            ctx.wait_idle()?;
            if let Some(fault) = ctx.take_fault() {
                return Err(fault.into());
            }
            self.collect_finished(ctx, &mut report);
            if self.last_frame_complete() {
                return Ok(report);
            }
            if Instant::now() > deadline {
                log::warn!(
                    "frame {}: GPU counts did not come back within 10 s",
                    self.frame_index
                );
                return Ok(report);
            }
            std::thread::sleep(Duration::from_millis(1));
        }
    }
}
