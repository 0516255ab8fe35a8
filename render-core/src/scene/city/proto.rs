//! The shared meshes every instance of the city draws (ground tile, sidewalk slab, five building
//! kinds, a tree, three cars), each modelled once at unit or real size; an instance's transform
//! sizes and places it.

use glam::Vec3;

use super::super::builtin::{MeshBuilder, SQUARE_RING, circle_ring, unit_ground_quad};
use super::super::{Mesh, MeshId};

/// The shared meshes, in the order of [`Scene::meshes`](crate::scene::Scene::meshes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Proto {
    GroundTile,
    Sidewalk,
    LowRise,
    MidRise,
    Setback,
    Plain,
    Tower,
    Tree,
    Sedan,
    Suv,
    Truck,
}

impl Proto {
    pub(super) const ALL: [Self; 11] = [
        Self::GroundTile,
        Self::Sidewalk,
        Self::LowRise,
        Self::MidRise,
        Self::Setback,
        Self::Plain,
        Self::Tower,
        Self::Tree,
        Self::Sedan,
        Self::Suv,
        Self::Truck,
    ];

    pub(super) fn id(self) -> MeshId {
        self as MeshId
    }

    pub(super) fn mesh(self) -> Mesh {
        let mut builder = MeshBuilder::default();
        match self {
            Self::GroundTile => return unit_ground_quad("ground_tile"),
            Self::Sidewalk => {
                builder.cuboid(Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 1.0, 0.5), false);
            }
            Self::LowRise | Self::MidRise | Self::Setback | Self::Plain | Self::Tower => {
                builder.lathe(Vec3::ZERO, &SQUARE_RING, &building_profile(self), true);
            }
            Self::Tree => {
                builder.lathe(
                    Vec3::ZERO,
                    &circle_ring(5),
                    &[[0.18, 0.0], [0.14, 2.4]],
                    false,
                );
                let crown = [[0.0, 1.9], [1.5, 2.5], [1.9, 3.7], [1.3, 4.9], [0.0, 5.5]];
                builder.lathe(Vec3::ZERO, &circle_ring(6), &crown, false);
            }
            Self::Sedan => {
                builder.cuboid(
                    Vec3::new(-2.25, 0.3, -0.9),
                    Vec3::new(2.25, 0.95, 0.9),
                    true,
                );
                builder.loft(
                    rect_at(-1.3, 1.0, 0.85, 0.95),
                    rect_at(-1.0, 0.35, 0.72, 1.45),
                    false,
                );
                add_wheels(&mut builder, &[-1.45, 1.45], 0.8, 0.33);
            }
            Self::Suv => {
                builder.cuboid(
                    Vec3::new(-2.3, 0.38, -0.95),
                    Vec3::new(2.3, 1.15, 0.95),
                    true,
                );
                builder.loft(
                    rect_at(-2.2, 0.9, 0.9, 1.15),
                    rect_at(-2.05, 0.2, 0.8, 1.8),
                    false,
                );
                add_wheels(&mut builder, &[-1.5, 1.5], 0.85, 0.38);
            }
            Self::Truck => {
                builder.cuboid(
                    Vec3::new(-3.1, 0.55, -1.15),
                    Vec3::new(1.2, 3.0, 1.15),
                    true,
                );
                builder.loft(
                    rect_at(1.3, 3.1, 1.1, 0.45),
                    rect_at(1.3, 2.5, 1.05, 2.5),
                    true,
                );
                add_wheels(&mut builder, &[-2.3, -1.3, 2.2], 0.95, 0.45);
            }
        }
        builder.build(self.mesh_name())
    }

    fn mesh_name(self) -> &'static str {
        match self {
            Self::GroundTile => "ground_tile",
            Self::Sidewalk => "sidewalk_slab",
            Self::LowRise => "building_lowrise",
            Self::MidRise => "building_midrise",
            Self::Setback => "building_setback",
            Self::Plain => "building_plain",
            Self::Tower => "tower",
            Self::Tree => "tree",
            Self::Sedan => "car_sedan",
            Self::Suv => "car_suv",
            Self::Truck => "car_truck",
        }
    }
}

/// A horizontal rectangle at height `y`: x from `x0` to `x1`, z within `half_z` of 0.
fn rect_at(x0: f32, x1: f32, half_z: f32, y: f32) -> [Vec3; 4] {
    [
        Vec3::new(x0, y, -half_z),
        Vec3::new(x1, y, -half_z),
        Vec3::new(x1, y, half_z),
        Vec3::new(x0, y, half_z),
    ]
}

/// A pair of 8-sided wheels at each of `axle_x`, centred `half_track` out from the middle.
fn add_wheels(builder: &mut MeshBuilder, axle_x: &[f32], half_track: f32, radius: f32) {
    const WHEEL_WIDTH_M: f32 = 0.25;
    for &x in axle_x {
        for side in [-1.0, 1.0] {
            let base = Vec3::new(x, radius, side * half_track - WHEEL_WIDTH_M * 0.5);
            builder.cylinder(base, Vec3::Z * WHEEL_WIDTH_M, radius, 8);
        }
    }
}

/// Window bands are recessed this far, parapets this wide and deep (unit footprint).
const WINDOW_INSET: f32 = 0.012;
const PARAPET_WIDTH: f32 = 0.02;
const PARAPET_DEPTH: f32 = 0.015;

/// The `[half width, height]` profile of a building kind with a unit footprint (x and z in
/// `[-0.5, 0.5]`), one unit tall, for [`MeshBuilder::lathe`] with a square ring.
pub(super) fn building_profile(kind: Proto) -> Vec<[f32; 2]> {
    let mut profile = Profile {
        points: vec![[0.5, 0.0]],
    };
    match kind {
        Proto::LowRise => {
            profile.floors(4, 0.96);
            profile.parapet(0.5, 1.0);
        }
        Proto::MidRise => {
            profile.floors(7, 0.975);
            profile.parapet(0.5, 1.0);
        }
        Proto::Setback => {
            profile.floors(6, 0.5);
            profile.step_to(0.4);
            profile.floors(4, 0.8);
            profile.step_to(0.3);
            profile.floors(2, 0.975);
            profile.parapet(0.3, 1.0);
        }
        Proto::Tower => {
            profile.floors(2, 0.08);
            profile.step_to(0.34);
            profile.floors(26, 0.84);
            profile.step_to(0.27);
            profile.floors(3, 0.92);
            profile.step_to(0.2);
            profile.up(0.95);
            // The spire.
            profile.step_to(0.015);
            profile.up(1.0);
        }
        _ => {
            // Shopfront, plain walls, a cornice and a parapet.
            profile.floors(1, 0.08);
            profile.step_to(0.49);
            profile.up(0.97);
            profile.parapet(0.5, 1.0);
        }
    }
    profile.points
}

/// A building profile being walked upwards.
struct Profile {
    points: Vec<[f32; 2]>,
}

impl Profile {
    fn last(&self) -> [f32; 2] {
        self.points.last().copied().unwrap_or([0.5, 0.0])
    }

    fn up(&mut self, y: f32) {
        let [half_width, _] = self.last();
        self.points.push([half_width, y]);
    }

    fn step_to(&mut self, half_width: f32) {
        let [_, y] = self.last();
        self.points.push([half_width, y]);
    }

    /// `count` floors up to `top_y`: each a solid spandrel under a recessed window band. Ends
    /// at the top of the last window band, so what follows steps out or in from there (stepping
    /// back out first would leave a zero-thickness sliver under a setback).
    fn floors(&mut self, count: u32, top_y: f32) {
        let [half_width, bottom_y] = self.last();
        let floor_height = (top_y - bottom_y) / count as f32;
        for floor in 0..count {
            let floor_y = bottom_y + floor as f32 * floor_height;
            if floor > 0 {
                self.step_to(half_width);
            }
            self.up(floor_y + 0.3 * floor_height);
            self.step_to(half_width - WINDOW_INSET);
            self.up(floor_y + floor_height);
        }
    }

    /// A wall of `half_width` up to `top_y`, ending in a parapet around a roof a little lower.
    fn parapet(&mut self, half_width: f32, top_y: f32) {
        self.step_to(half_width);
        self.up(top_y);
        self.step_to(half_width - PARAPET_WIDTH);
        self.points
            .push([half_width - PARAPET_WIDTH, top_y - PARAPET_DEPTH]);
    }
}
