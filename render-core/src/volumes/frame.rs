//! The volume passes' uniforms for one frame (`VolumeFrame` in `volumes/common.wgsl`): the
//! light's frame and the receiver grid over the scene, the camera's near rectangle in it (for
//! the z-pass test), the options, and discrete clamping's slices of the picture.

use glam::Vec3;

use super::pipelines::{
    BIG_CASTERS, BIG_LANES, CULL_LANES, DEPTH_BINS, RECEIVER_CELLS, VolumeFrameGpu,
};
use super::scene::SceneVolumes;
use crate::culling::codes::culled_code;
use crate::culling::{Method, StageKind};
use crate::geom::{Camera, basis_for_direction};
use crate::shadow_view::{VolumeClamp, VolumePassChoice, VolumeSettings};
use crate::technique::TechniqueInput;

/// This frame's uniforms: `method` the effective one, `slices` the clamping's, and the
/// calibrated pixels per volume vertex.
pub(super) fn uniforms(
    input: &TechniqueInput<'_>,
    scene: &SceneVolumes,
    method: Method,
    (slices, pixels_per_vertex): (u32, f32),
    adapter: wgpu::DeviceType,
) -> VolumeFrameGpu {
    let bounds = input.scene.bounds();
    let reach = if bounds.is_empty() {
        1.0
    } else {
        bounds.extent().length() * 1.01 + 1.0
    };
    let to_light = input.direction_to_sun.normalize_or(Vec3::Y);
    // The receiver grid covers the scene across the light.
    let travel = -to_light;
    let (right, up) = basis_for_direction(travel.as_dvec3());
    let (right, up) = (right.as_vec3(), up.as_vec3());
    let corners = if bounds.is_empty() {
        [Vec3::ZERO; 8]
    } else {
        bounds.corners()
    };
    let range = |axis: Vec3| {
        corners
            .iter()
            .map(|c| c.dot(axis))
            .fold((f32::MAX, f32::MIN), |(lo, hi), d| (lo.min(d), hi.max(d)))
    };
    let (x, y, z) = (range(right), range(up), range(travel));
    let point = input.point_light.map(|p| p.position);
    let (grid, cell) = receiver_grid(slices, point.is_some(), (x.1 - x.0, y.1 - y.0));
    // The grid's depth bins span the scene's depths along the sun, or its reach from a lamp.
    let depth_bin = if point.is_some() { reach } else { z.1 - z.0 }.max(1e-3) / DEPTH_BINS as f32;
    let clamp = input.volumes.clamp;
    let budget = StepBudget::of(adapter, &input.volumes);
    // A point light's rays cross planes through the eye that hold the axis across the view
    // and the way to the light, in turn, as the sun's cross the sun's slicing planes.
    let slicing = slicing(
        input.camera,
        input.aspect,
        point.map_or(to_light, |p| (p - input.camera.eye).normalize_or(to_light)),
    );
    // The near rectangle's box in the light's frame, as `in_light` places points.
    let near = input.camera.frustum_corners_world(
        f64::from(input.aspect),
        f64::from(input.camera.near_m),
        f64::from(input.camera.near_m) * 2.0,
    );
    let origin = Vec3::new(x.0, y.0, z.0);
    let (near_lo, near_hi) = near[..4].iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), corner| {
            let c = corner.as_vec3();
            let p = Vec3::new(c.dot(right), c.dot(up), c.dot(travel)) - origin;
            (lo.min(p), hi.max(p))
        },
    );
    VolumeFrameGpu {
        to_light: to_light.extend(reach).to_array(),
        counts: [
            scene.edge_items,
            scene.triangle_items,
            scene.casters,
            culled_code(StageKind::ReceiverMask),
        ],
        options: [
            scene.instances,
            u32::from(method != Method::None)
                | (u32::from(clamp != VolumeClamp::None) << 1)
                | (u32::from(clamp == VolumeClamp::Discrete) << 2)
                | (u32::from(given_intervals(clamp, point.is_some())) << 3)
                | (u32::from(!input.volumes.strips) << 4),
            budget.cull_lanes,
            match input.volumes.pass {
                VolumePassChoice::Auto => 0,
                VolumePassChoice::ZPass => 1,
                VolumePassChoice::ZFail => 2,
            },
        ],
        right: right.extend(x.0).to_array(),
        up: up.extend(y.0).to_array(),
        travel: travel.extend(z.0).to_array(),
        cell: [
            cell,
            pixels_per_vertex,
            depth_bin,
            budget.cell_points as f32,
        ],
        steps: [
            budget.caster,
            budget.lane,
            budget.big_casters,
            budget.lanes_per_big_caster(),
        ],
        near_lo: near_lo.extend(0.0).to_array(),
        near_hi: near_hi.extend(0.0).to_array(),
        slicing,
        grid,
        point: point.map_or([0.0; 4], |p| p.extend(1.0).to_array()),
        near_planes: point.map_or([[0.0, 0.0, 0.0, 1.0]; 5], |p| {
            let near: Vec<Vec3> = near[..4].iter().map(|c| c.as_vec3()).collect();
            // Corners in turn round the rectangle.
            pyramid_planes(p, [near[0], near[1], near[3], near[2]])
        }),
        picture: [1.0, 1.0, 0.0, 0.0],
    }
}

/// Whether the CPU gives the casters' intervals (`options.y` bit 3): exact clamping's, and
/// clamping by boxes' under the sun.
fn given_intervals(clamp: VolumeClamp, point: bool) -> bool {
    clamp == VolumeClamp::Exact || (clamp == VolumeClamp::Boxes && !point)
}

/// How much looping the cull of one frame may do per invocation
/// (`VolumeFrame::steps` in `volumes/common.wgsl`), by the adapter's kind.
///
/// Each caster is culled by one workgroup, whose first `cull_lanes` lanes share its cells
/// and their receiver points (`gather_footprint` in `volumes/grid.wgsl`). Past `caster` loop
/// iterations in a lane it is handed to workgroups of its own (`volumes/big_casters.wgsl`),
/// up to `big_casters` of them a frame, whose `lanes_per_big_caster()` lanes share its
/// cells, each within `lane` iterations; past either, its volume is kept whole (counted in
/// the report).
///
/// llvmpipe ends every loop of a shader, silently, once 65,535 iterations of all its loops
/// have run, counted for the eight invocations it runs side by side (Mesa's
/// `LP_MAX_TGSI_LOOP_ITERATIONS`): an eighth of that, less the test's other loops, keeps
/// every caster whole or exact there. A GPU has no such limit, but one lane's loop is
/// serial, and the dispatch lasts as long as its longest lane: on an H200 a floor walked by
/// one invocation (up to 2^20 iterations) held it for 180 ms, and a step of the cull costs
/// about 2 µs there, so the cull's time followed the budget (0.96 ms at 512 steps, 4.3 at
/// 2,048 on the robots). There a caster gets 32 lanes of 512 steps, a big one 4,096 lanes,
/// and a cell dense with points (near the camera, hundreds of pixels) gives its depths
/// whole past `cell_points` per lane (README, "Shadow volumes measured on a GPU"). A CPU
/// adapter runs lanes one after another: 4 share a caster there, enough to take the same
/// path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct StepBudget {
    /// Lanes of `cull_casters`' workgroup that share a caster (1 to 32, `CULL_LANES`).
    pub cull_lanes: u32,
    /// Loop iterations one of them may take on a caster.
    pub caster: u32,
    /// Loop iterations one lane of a big caster's workgroups may take.
    pub lane: u32,
    /// The most casters a frame hands to workgroups (at most `BIG_CASTERS`).
    pub big_casters: u32,
    /// Workgroups of `BIG_LANES` lanes per big caster.
    pub groups_per_big_caster: u32,
    /// The most receiver points of one grid cell tested one by one against a caster; a
    /// cell with more gives its depths whole, as discrete clamping's cells do.
    pub cell_points: u32,
}

impl StepBudget {
    /// The adapter's budget, with the user's caster budget and cell points where set (on a
    /// CPU adapter no more steps than its own).
    pub(super) fn of(adapter: wgpu::DeviceType, settings: &VolumeSettings) -> Self {
        let budget = Self::of_adapter(adapter);
        let most = if adapter == wgpu::DeviceType::Cpu {
            budget.caster
        } else {
            1 << 24
        };
        Self {
            caster: settings
                .cull_steps
                .map_or(budget.caster, |steps| steps.clamp(1, most)),
            cell_points: settings.cell_points.unwrap_or(budget.cell_points),
            cull_lanes: settings
                .cull_lanes
                .map_or(budget.cull_lanes, |lanes| lanes.clamp(1, CULL_LANES)),
            ..budget
        }
    }

    fn of_adapter(adapter: wgpu::DeviceType) -> Self {
        match adapter {
            wgpu::DeviceType::Cpu => Self {
                cull_lanes: 4,
                caster: 65_535 / 8 - 1_200,
                lane: 65_535 / 8 - 1_200,
                big_casters: 64,
                groups_per_big_caster: 2,
                cell_points: u32::MAX,
            },
            _ => Self {
                cull_lanes: CULL_LANES,
                caster: 512,
                lane: 16_384,
                big_casters: BIG_CASTERS,
                groups_per_big_caster: 16,
                cell_points: 16,
            },
        }
    }

    pub(super) fn lanes_per_big_caster(self) -> u32 {
        BIG_LANES * self.groups_per_big_caster
    }
}

/// The receiver grid's layout (`VolumeFrame::grid`, `volumes/grid.wgsl`) and its cell size,
/// metres, for `slices` slices of the view: for the sun, square cells over the scene's
/// `extent` across it, as small as [`RECEIVER_CELLS`] of them allow; for a point light, the
/// six faces of a cube around it, three across and two down, each of the most cells a side
/// that fit, with cells of size 1 (`volumes/point_light.wgsl`).
fn receiver_grid(slices: u32, point: bool, extent: (f32, f32)) -> ([u32; 4], f32) {
    if point {
        let face = ((RECEIVER_CELLS / 6) as f32).sqrt() as u32;
        return ([slices, 3 * face, 2 * face, face], 1.0);
    }
    let (wide, high) = (extent.0.max(1e-3), extent.1.max(1e-3));
    let cells = RECEIVER_CELLS as f32;
    let mut cell = (wide * high / cells)
        .sqrt()
        .max(wide.max(high) / cells)
        .max(1e-3);
    loop {
        let (columns, rows) = ((wide / cell).ceil() as u32, (high / cell).ceil() as u32);
        let (columns, rows) = (columns.max(1), rows.max(1));
        if u64::from(columns) * u64::from(rows) <= u64::from(RECEIVER_CELLS) {
            return ([slices, columns, rows, 0], cell);
        }
        cell *= 1.01;
    }
}

/// The planes of the pyramid from `apex` to the quadrilateral `base` (xyz: normal, w: offset;
/// the pyramid on their positive side): its four sides and its base. A flat pyramid (the
/// apex in the base's plane) gets planes nothing lies outside of.
fn pyramid_planes(apex: Vec3, base: [Vec3; 4]) -> [[f32; 4]; 5] {
    let inside = (apex + base.iter().copied().sum::<Vec3>()) / 5.0;
    let plane = |a: Vec3, b: Vec3, c: Vec3| -> Option<[f32; 4]> {
        let n = (b - a).cross(c - a).try_normalize()?;
        let d = -n.dot(a);
        let flip = if n.dot(inside) + d < 0.0 { -1.0 } else { 1.0 };
        let slack = 1e-4 * (1.0 + a.length());
        ((n.dot(inside) + d).abs() > slack).then(|| (n * flip).extend(d * flip + slack).to_array())
    };
    let mut planes = [[0.0, 0.0, 0.0, 1.0]; 5];
    for k in 0..4 {
        match plane(apex, base[k], base[(k + 1) % 4]) {
            Some(p) => planes[k] = p,
            None => return [[0.0, 0.0, 0.0, 1.0]; 5],
        }
    }
    match plane(base[0], base[1], base[2]) {
        Some(p) => planes[4] = p,
        None => return [[0.0, 0.0, 0.0, 1.0]; 5],
    }
    planes
}

/// Discrete clamping's slices in the picture (`slicing` in `volumes/common.wgsl`): planes
/// through the eye that hold the axis across both the light and the view direction, so each
/// meets the picture in a line along that axis and the slices are parallel strips (Lloyd
/// 3.2.2). Returns the strip coordinate's weights on the NDC axes and its half-range, then
/// the far plane.
fn slicing(camera: &Camera, aspect: f32, to_light: Vec3) -> [f32; 4] {
    let forward = camera.forward.normalize_or(Vec3::NEG_Z);
    let (right, up) = camera.basis();
    // Across the light and the view; looking along the light, any axis of the picture.
    let axis = to_light.cross(forward).try_normalize().unwrap_or(right);
    // The strips run along `axis`: their coordinate is along the picture's other axis.
    let across = axis.cross(forward).normalize_or(up);
    let tan_y = (camera.fov_y_rad * 0.5).tan();
    let weights = glam::Vec2::new(across.dot(right) * tan_y * aspect, across.dot(up) * tan_y);
    [
        weights.x,
        weights.y,
        weights.x.abs() + weights.y.abs(),
        camera.far_m,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_users_budget_stays_within_what_each_adapter_can_run() {
        let settings = |cull_steps, cull_lanes| VolumeSettings {
            cull_steps,
            cull_lanes,
            ..VolumeSettings::default()
        };
        let cpu = StepBudget::of(wgpu::DeviceType::Cpu, &VolumeSettings::default());
        assert_eq!(
            (cpu.cull_lanes, cpu.caster, cpu.lanes_per_big_caster()),
            (4, 6_991, 512)
        );
        let gpu = StepBudget::of(wgpu::DeviceType::DiscreteGpu, &VolumeSettings::default());
        assert_eq!(
            (
                gpu.cull_lanes,
                gpu.caster,
                gpu.cell_points,
                gpu.lanes_per_big_caster()
            ),
            (32, 512, 16, 4_096)
        );
        // llvmpipe ends long loops silently: no more steps than its own there.
        let asked = settings(Some(100_000), Some(64));
        let cpu = StepBudget::of(wgpu::DeviceType::Cpu, &asked);
        assert_eq!((cpu.caster, cpu.cull_lanes), (6_991, CULL_LANES));
        // A GPU's budget stays a positive i32 in the shader.
        let gpu = StepBudget::of(
            wgpu::DeviceType::IntegratedGpu,
            &settings(Some(u32::MAX), Some(0)),
        );
        assert_eq!((gpu.caster, gpu.cull_lanes), (1 << 24, 1));
        let gpu = StepBudget::of(wgpu::DeviceType::DiscreteGpu, &settings(Some(0), Some(8)));
        assert_eq!((gpu.caster, gpu.cull_lanes), (1, 8));
    }
}
