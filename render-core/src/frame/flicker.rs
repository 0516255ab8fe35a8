//! Flicker: with the scene still, the counted pixels whose shadow changes when only the camera
//! moves by 1 cm or turns by 0.1 degrees. Both frames' shadows are read at the first frame's
//! surface points (the exact shadow's, `truth/`), so what is counted is the shadow moving on
//! the surface, not the surface moving in the picture, and only at the points the other
//! camera sees too: a culling method owes no shadow to a receiver out of view. Stabilised
//! cascades (a texel-snapped sphere per slice, chosen by distance from the eye) keep every
//! map's texel grid fixed in the world and give 0.

use glam::{Quat, Vec3};
use serde::Serialize;

use super::{FrameInput, FrameRenderer, SceneGpu};
use crate::geom::Camera;
use crate::gpu::{GpuContext, GpuError};
use crate::scene::Scene;
use crate::truth::{SHADOWED_BELOW, TruthCache, seen_from};

/// How far the camera moves, metres.
pub const FLICKER_MOVE_M: f32 = 0.01;
/// How far it turns about the world's up, degrees.
pub const FLICKER_TURN_DEG: f32 = 0.1;

/// Pixels whose shadow changed, of those counted (the first view's visible receivers facing
/// the sun) that the other camera sees too.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Flicker {
    /// After moving 1 cm to the camera's right.
    pub moved_px: u32,
    /// After turning 0.1 degrees to the left.
    pub turned_px: u32,
    pub counted_px: u32,
    /// Of the counted pixels, those the moved camera sees.
    pub moved_seen_px: u32,
    /// Of the counted pixels, those the turned camera sees.
    pub turned_seen_px: u32,
}

/// `camera` moved by [`FLICKER_MOVE_M`] to its right.
pub fn moved(camera: &Camera) -> Camera {
    let (right, _) = camera.basis();
    Camera {
        eye: camera.eye + right * FLICKER_MOVE_M,
        ..*camera
    }
}

/// `camera` turned by [`FLICKER_TURN_DEG`] about the world's up.
pub fn turned(camera: &Camera) -> Camera {
    let up = camera.world_up.normalize_or(Vec3::Y);
    Camera {
        forward: Quat::from_axis_angle(up, FLICKER_TURN_DEG.to_radians()) * camera.forward,
        ..*camera
    }
}

impl FrameRenderer {
    /// Renders `input`'s view, then the moved and the turned view, and counts the points of
    /// the first view whose shadow differs between the first frame and each of the others.
    /// Leaves the renderer after the turned frame. Blocks.
    pub fn flicker(
        &mut self,
        ctx: &GpuContext,
        (scene, scene_gpu): (&Scene, &SceneGpu),
        truth: &mut TruthCache,
        input: &FrameInput<'_>,
    ) -> Result<Flicker, GpuError> {
        let exact = truth.exact(
            scene,
            input.camera,
            (input.width, input.height),
            input.settings.shadow_light(),
        );
        let points = exact.points.clone();
        let aspect = input.width.max(1) as f32 / input.height.max(1) as f32;
        let rays = truth.rays(scene);
        let (moved_camera, turned_camera) = (moved(input.camera), turned(input.camera));
        let seen = [&moved_camera, &turned_camera].map(|c| seen_from(rays, c, aspect, &points));
        self.render_and_wait(ctx, scene, scene_gpu, input)?;
        let first = self.light_at(ctx, &points)?;
        let mut changed = |camera: &Camera, seen: &[bool]| -> Result<u32, GpuError> {
            self.render_and_wait(ctx, scene, scene_gpu, &FrameInput { camera, ..*input })?;
            let then = self.light_at(ctx, &points)?;
            Ok(first
                .iter()
                .zip(&then)
                .zip(seen)
                .filter(|((a, b), seen)| {
                    **seen && ((**a < SHADOWED_BELOW) != (**b < SHADOWED_BELOW))
                })
                .count() as u32)
        };
        let seen_count = |s: &[bool]| s.iter().filter(|s| **s).count() as u32;
        Ok(Flicker {
            moved_px: changed(&moved_camera, &seen[0])?,
            turned_px: changed(&turned_camera, &seen[1])?,
            counted_px: points.len() as u32,
            moved_seen_px: seen_count(&seen[0]),
            turned_seen_px: seen_count(&seen[1]),
        })
    }
}
