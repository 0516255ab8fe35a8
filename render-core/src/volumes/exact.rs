//! Exact clamping (`--volume-clamp exact`), the limit every clamping is measured against, as
//! Lloyd et al.'s `CCe` is (their exact intervals of receivers' oriented boxes in the volume):
//! per caster, the depths along the light of the visible receiver points that its own
//! triangles shadow, found by a ray from each point towards the light through the truth's
//! trees (`truth/`), on the CPU. Every caster that shadows no visible point is culled; the
//! others get the occupied depths cut at their largest gaps into at most `MAX_INTERVALS`
//! intervals, which `find.wgsl` merges and turns into extrusions as it does its own.
//! Seconds per frame on big views, as Lloyd's took: a measure, not a way to draw.

use glam::Vec3;

use super::pipelines::MAX_INTERVALS;
use super::scene::SceneVolumes;
use crate::geom::Camera;
use crate::gpu::GpuContext;
use crate::scene::{Scene, ShadowLight};
use crate::technique::TechniqueInput;
use crate::truth::{ExactShadow, SceneRays, ViewKey, rows_in_parallel};

/// The trees of the scene the intervals are cast through, built on first use.
#[derive(Default)]
pub(super) struct ExactClamp {
    rays: Option<(u64, SceneRays)>,
}

/// The view the intervals are for, and how the light measures depth.
pub(super) struct ExactView<'a> {
    pub camera: &'a Camera,
    pub size: (u32, u32),
    pub light: ShadowLight,
    /// A point's depth along the light (as `find.wgsl` measures it for the grid).
    pub depth_of: &'a (dyn Fn(Vec3) -> f32 + Sync),
}

/// An unused interval slot: `find.wgsl` stops at the first.
pub(super) const NO_INTERVAL: [f32; 2] = [0.0, -1.0];

impl ExactClamp {
    /// Casts this frame's exact intervals and writes them into the casters' interval slots,
    /// where `find.wgsl` reads them (`given_intervals`). `travel`: the sun's frame along the
    /// light (`VolumeFrame::travel`), as the grid measures depth.
    pub fn write(
        &mut self,
        ctx: &GpuContext,
        input: &TechniqueInput<'_>,
        scene: &SceneVolumes,
        (size, travel): ((u32, u32), [f32; 4]),
    ) {
        let light = input
            .point_light
            .map_or(ShadowLight::Sun(input.direction_to_sun), |p| {
                p.shadow_light()
            });
        let along = Vec3::from_slice(&travel[..3]);
        let depth_of = move |p: Vec3| match light {
            ShadowLight::Sun(_) => (p.dot(along) - travel[3]).max(0.0),
            ShadowLight::Point(at) | ShadowLight::Spot(at, _) => p.distance(at),
        };
        let view = ExactView {
            camera: input.camera,
            size,
            light,
            depth_of: &depth_of,
        };
        let intervals = self.intervals(
            input.scene,
            scene.scene_id,
            &view,
            &scene.caster_of,
            scene.casters,
        );
        ctx.queue
            .write_buffer(&scene.intervals, 0, bytemuck::cast_slice(&intervals));
    }

    /// Per caster (`caster_of`: each instance's caster), `MAX_INTERVALS` depth intervals,
    /// the unused ones [`NO_INTERVAL`].
    pub fn intervals(
        &mut self,
        scene: &Scene,
        scene_id: u64,
        view: &ExactView<'_>,
        caster_of: &[Option<u32>],
        casters: u32,
    ) -> Vec<[f32; 2]> {
        match &mut self.rays {
            Some((id, rays)) if *id == scene_id => rays.sync(&scene.instances),
            slot => *slot = Some((scene_id, SceneRays::new(scene))),
        }
        let rays = &self.rays.as_ref().expect("built above").1;
        let key = ViewKey {
            camera: *view.camera,
            width: view.size.0,
            height: view.size.1,
            light: view.light,
            poses: rays.version,
        };
        let exact = ExactShadow::cast(rays, key);
        let shadowing = shadowing_casters(rays, &exact, view, caster_of);
        let mut depths: Vec<Vec<f32>> = vec![Vec::new(); casters as usize];
        for (caster, depth) in shadowing {
            depths[caster as usize].push(depth);
        }
        depths.into_iter().flat_map(|d| occupied(&d)).collect()
    }
}

/// Every (caster, depth) pair of a shadowed exact point and a caster on its way to the light,
/// on every core.
fn shadowing_casters(
    rays: &SceneRays,
    exact: &ExactShadow,
    view: &ExactView<'_>,
    caster_of: &[Option<u32>],
) -> Vec<(u32, f32)> {
    const CHUNK: usize = 2048;
    let shadowed: Vec<usize> = (0..exact.points.len())
        .filter(|&i| exact.shadowed(i))
        .collect();
    let chunks = shadowed.len().div_ceil(CHUNK) as u32;
    rows_in_parallel(chunks, |c| {
        let start = c as usize * CHUNK;
        let mut found = Vec::new();
        for &i in &shadowed[start..(start + CHUNK).min(shadowed.len())] {
            let p = Vec3::from_slice(&exact.points[i].position[..3]);
            let depth = (view.depth_of)(p);
            let (towards, distance) = view.light.towards(p);
            rays.blockers(exact.leaving[i], towards, (0.0, distance), |instance| {
                if let Some(Some(caster)) = caster_of.get(instance as usize) {
                    found.push((*caster, depth));
                }
            });
        }
        found
    })
    .into_iter()
    .flatten()
    .collect()
}

/// The occupied intervals of one caster's `depths`: cut at the largest gaps into at most
/// `MAX_INTERVALS`, padded with [`NO_INTERVAL`].
fn occupied(depths: &[f32]) -> [[f32; 2]; MAX_INTERVALS as usize] {
    occupied_spans(depths.iter().map(|&d| [d, d]).collect())
}

/// `spans` of depth merged where they overlap or touch, then cut at the largest gaps between
/// them into at most `MAX_INTERVALS`, padded with [`NO_INTERVAL`].
pub(super) fn occupied_spans(mut spans: Vec<[f32; 2]>) -> [[f32; 2]; MAX_INTERVALS as usize] {
    let mut out = [NO_INTERVAL; MAX_INTERVALS as usize];
    spans.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]));
    let mut merged: Vec<[f32; 2]> = Vec::new();
    for span in spans {
        match merged.last_mut() {
            Some(last) if span[0] <= last[1] => last[1] = last[1].max(span[1]),
            _ => merged.push(span),
        }
    }
    if merged.is_empty() {
        return out;
    }
    // The gaps to keep: the largest, in depth order.
    let mut gaps: Vec<usize> = (1..merged.len()).collect();
    gaps.sort_unstable_by(|&a, &b| {
        (merged[b][0] - merged[b - 1][1]).total_cmp(&(merged[a][0] - merged[a - 1][1]))
    });
    gaps.truncate(MAX_INTERVALS as usize - 1);
    gaps.sort_unstable();
    let mut start = 0;
    for (slot, end) in gaps.into_iter().chain([merged.len()]).enumerate() {
        out[slot] = [merged[start][0], merged[end - 1][1]];
        start = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depths_are_cut_at_their_largest_gaps_into_at_most_four_intervals() {
        let depths = [5.0, 1.0, 1.5, 9.0, 9.2, 20.0, 2.0, 30.0];
        assert_eq!(
            occupied(&depths),
            [[1.0, 5.0], [9.0, 9.2], [20.0, 20.0], [30.0, 30.0]]
        );
        let two = [3.0, 1.0];
        assert_eq!(
            occupied(&two),
            [[1.0, 1.0], [3.0, 3.0], NO_INTERVAL, NO_INTERVAL]
        );
        assert_eq!(occupied(&[]), [NO_INTERVAL; 4]);
        let same = [2.0, 2.0, 2.0];
        assert_eq!(
            occupied(&same),
            [[2.0, 2.0], NO_INTERVAL, NO_INTERVAL, NO_INTERVAL]
        );
    }
}
