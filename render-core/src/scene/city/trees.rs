//! Trees: street trees along the kerb and trees on a jittered grid in parks.

use std::f32::consts::TAU;

use glam::{Mat4, Quat, Vec2, Vec3};

use super::{BlockNames, CityBuilder, KERB_HEIGHT_M, Mobility, Proto, RectXz};

/// Street trees stand this far in from the kerb, at most this far apart.
const STREET_TREE_INSET_M: f32 = 2.3;
const STREET_TREE_SPACING_M: f32 = 12.0;
const STREET_TREE_CHANCE: f32 = 0.5;
/// Tree scale range; crowns are at most 1.9 m wide times the scale.
const TREE_SCALE: [f32; 2] = [0.8, 1.2];
/// Trees in parks keep this far from the park's edge, so their crowns stay inside it.
const TREE_CLEARANCE_M: f32 = 2.3;

/// Linear RGB foliage colours.
const FOLIAGE: [[f32; 3]; 3] = [[0.05, 0.18, 0.04], [0.08, 0.22, 0.05], [0.10, 0.16, 0.03]];

impl CityBuilder<'_> {
    /// Trees along the kerb on every side of `block`, some slots left empty.
    pub(super) fn add_street_trees(&mut self, names: &mut BlockNames, block: RectXz) {
        let line = block.shrunk(STREET_TREE_INSET_M);
        let corners = [
            line.min,
            Vec2::new(line.max.x, line.min.y),
            line.max,
            Vec2::new(line.min.x, line.max.y),
        ];
        for k in 0..4 {
            let (from, to) = (corners[k], corners[(k + 1) % 4]);
            let slots = (from.distance(to) / STREET_TREE_SPACING_M).floor() as u32;
            for slot in 0..slots {
                if self.rng.chance(STREET_TREE_CHANCE) {
                    self.add_tree(names, from.lerp(to, (slot as f32 + 0.5) / slots as f32));
                }
            }
        }
    }

    /// Trees on a jittered grid of `spacing_m` inside `area`, each cell planted with `chance`.
    pub(super) fn add_trees_in(
        &mut self,
        names: &mut BlockNames,
        area: RectXz,
        spacing_m: f32,
        chance: f32,
    ) {
        let inner = area.shrunk(TREE_CLEARANCE_M);
        let cells = (inner.size() / spacing_m).floor().max(Vec2::ONE);
        let cell_size = inner.size() / cells;
        for row in 0..cells.y as u32 {
            for column in 0..cells.x as u32 {
                let jitter = Vec2::new(
                    self.rng.range_f32(0.25, 0.75),
                    self.rng.range_f32(0.25, 0.75),
                );
                if self.rng.chance(chance) {
                    self.add_tree(
                        names,
                        inner.min + (Vec2::new(column as f32, row as f32) + jitter) * cell_size,
                    );
                }
            }
        }
    }

    fn add_tree(&mut self, names: &mut BlockNames, position: Vec2) {
        let scale = self.rng.range_f32(TREE_SCALE[0], TREE_SCALE[1]);
        let yaw = self.rng.range_f32(0.0, TAU);
        let color = self.pick_color(&FOLIAGE);
        let world_from_local = Mat4::from_scale_rotation_translation(
            Vec3::splat(scale),
            Quat::from_rotation_y(yaw),
            Vec3::new(position.x, KERB_HEIGHT_M, position.y),
        );
        self.place(
            names.next("tree"),
            Proto::Tree,
            world_from_local,
            color,
            Mobility::Static,
        );
    }
}
