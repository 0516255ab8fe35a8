//! Continuous clamping as Lloyd et al. do it (`--volume-clamp boxes`, their 3.2.1, object
//! precision, on the CPU): every caster's and every potential receiver's world box in the
//! sun's frame; the potential receivers are the receiving instances whose boxes meet the
//! camera's view (the paper's corridor computes them by view-frustum culling alone). Boxes
//! that overlap across the light are found by sweep-and-prune along the light's first axis
//! (`SweepAndPrune`, its order kept from the last frame), then tested on the second. Per
//! caster, the depth intervals of the receivers' boxes it overlaps, from its own nearest
//! depth on, are merged and cut at their largest gaps into at most `MAX_INTERVALS`, and
//! written into its interval slots as exact clamping's are, for `find.wgsl` to merge by the
//! V > R rule and extrude. A caster over no potential receiver is culled. The grid's
//! `continuous` does the same per visible pixel, on the GPU; this is the paper's measure of
//! what boxes give, and of the CPU time they cost.

use glam::Vec3;

use super::exact::occupied_spans;
use super::scene::SceneVolumes;
use super::sweep_prune::SweepAndPrune;
use crate::geom::Frustum;
use crate::gpu::GpuContext;
use crate::scene::Scene;
use crate::technique::TechniqueInput;

/// The sun's frame as the grid measures it (`VolumeFrame::right`, `up`, `travel`): axes
/// (xyz) and where each starts (w).
pub(super) type LightFrame = [[f32; 4]; 3];

/// The last frame's work: the potential receivers, the caster and receiver pairs whose boxes
/// overlap and the sort's swaps (its CPU time is the technique's clamping time).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct BoxClampStats {
    pub receivers: u32,
    pub pairs: u32,
    pub swaps: u64,
}

/// The sort's order between frames, and the last frame's work.
#[derive(Default)]
pub(super) struct BoxClamp {
    sweep: SweepAndPrune,
    pub last: Option<BoxClampStats>,
    /// Whether the last frame asked for boxes under a point light (clamped `continuous`).
    pub under_point: bool,
}

/// An instance's box in the sun's frame, and its roles.
struct LightBox {
    lo: Vec3,
    hi: Vec3,
    caster: Option<u32>,
    receiver: bool,
}

impl BoxClamp {
    /// This frame's intervals into the casters' interval slots (`given_intervals` in
    /// `find.wgsl` reads them).
    pub fn write(
        &mut self,
        ctx: &GpuContext,
        input: &TechniqueInput<'_>,
        scene: &SceneVolumes,
        frame: LightFrame,
    ) {
        let view = Frustum::from_clip_from_world(&input.camera.clip_from_world(input.aspect));
        let intervals =
            self.intervals(input.scene, &view, (&scene.caster_of, scene.casters), frame);
        ctx.queue
            .write_buffer(&scene.intervals, 0, bytemuck::cast_slice(&intervals));
    }

    /// Per caster (`casters.0`: each instance's caster, of `casters.1`), `MAX_INTERVALS`
    /// depth intervals, the unused ones `NO_INTERVAL`.
    pub fn intervals(
        &mut self,
        scene: &Scene,
        view: &Frustum,
        (caster_of, casters): (&[Option<u32>], u32),
        frame: LightFrame,
    ) -> Vec<[f32; 2]> {
        let axes = frame.map(|a| Vec3::new(a[0], a[1], a[2]));
        let origin = Vec3::new(frame[0][3], frame[1][3], frame[2][3]);
        let boxes: Vec<LightBox> = scene
            .instances
            .iter()
            .zip(caster_of)
            .filter_map(|(instance, caster)| {
                let receiver =
                    instance.receives_shadow && view.intersects_aabb(&instance.aabb_in_world);
                if caster.is_none() && !receiver {
                    return None;
                }
                let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
                for corner in instance.aabb_in_world.corners() {
                    let p = Vec3::new(
                        corner.dot(axes[0]),
                        corner.dot(axes[1]),
                        corner.dot(axes[2]),
                    );
                    lo = lo.min(p - origin);
                    hi = hi.max(p - origin);
                }
                // Depths are past the scene's nearest; a millimetre and a bit of the box
                // to spare, as the grid pads casters.
                let pad = Vec3::splat(1e-3) + (hi - lo).abs() * 1e-5;
                Some(LightBox {
                    lo: (lo - pad).with_z((lo.z - pad.z).max(0.0)),
                    hi: hi + pad,
                    caster: *caster,
                    receiver,
                })
            })
            .collect();
        let mut spans: Vec<Vec<[f32; 2]>> = vec![Vec::new(); casters as usize];
        let mut pairs = 0;
        let mut shadows = |c: &LightBox, r: &LightBox| {
            let Some(caster) = c.caster else {
                return;
            };
            if r.receiver && c.lo.y <= r.hi.y && r.lo.y <= c.hi.y && r.hi.z >= c.lo.z {
                spans[caster as usize].push([r.lo.z.max(c.lo.z), r.hi.z]);
                pairs += 1;
            }
        };
        for b in &boxes {
            // A caster over its own receiving surface shadows itself.
            shadows(b, b);
        }
        let extents: Vec<(f32, f32)> = boxes.iter().map(|b| (b.lo.x, b.hi.x)).collect();
        self.sweep.overlaps(&extents, |a, b| {
            let (a, b) = (&boxes[a as usize], &boxes[b as usize]);
            shadows(a, b);
            shadows(b, a);
        });
        let intervals = spans.into_iter().flat_map(occupied_spans).collect();
        self.last = Some(BoxClampStats {
            receivers: boxes.iter().filter(|b| b.receiver).count() as u32,
            pairs,
            swaps: self.sweep.swaps,
        });
        intervals
    }
}
