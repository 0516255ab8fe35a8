//! Cars: parked in slots along every lane of every street segment, each driving along its lane
//! when the scene animates.

use glam::{Mat4, Quat, Vec2, Vec3};

use super::{CityBuilder, Mobility, Motion, Proto};

const LANE_WIDTH_M: f32 = 4.0;
/// Cars keep this far from intersections and stand in slots this far apart.
const CAR_END_MARGIN_M: f32 = 2.0;
const CAR_SPACING_M: f32 = 7.5;
const CAR_CHANCE: f32 = 0.11;

/// Linear RGB car paints.
const CAR_PAINT: [[f32; 3]; 8] = [
    [0.60, 0.03, 0.03],
    [0.03, 0.10, 0.45],
    [0.80, 0.80, 0.78],
    [0.02, 0.02, 0.02],
    [0.45, 0.46, 0.48],
    [0.85, 0.60, 0.02],
    [0.05, 0.25, 0.10],
    [0.30, 0.05, 0.20],
];

impl CityBuilder<'_> {
    /// Cars on every street segment between two intersections, in every lane.
    pub(super) fn add_cars(&mut self) {
        let params = *self.params;
        let (ground, pitch) = (params.ground_rect(), params.pitch_m());
        let half_street = params.street_width_m * 0.5;
        // Streets along x (one per row of kerbs), then streets along z.
        for j in 0..=params.blocks_z {
            let center_z = ground.min.y + half_street + j as f32 * pitch.y;
            for i in 0..params.blocks_x {
                let block = params.block_rect(i, 0);
                self.add_segment_cars(Vec2::new(block.min.x, center_z), Vec2::X, block.size().x);
            }
        }
        for i in 0..=params.blocks_x {
            let center_x = ground.min.x + half_street + i as f32 * pitch.x;
            for j in 0..params.blocks_z {
                let block = params.block_rect(0, j);
                self.add_segment_cars(Vec2::new(center_x, block.min.y), Vec2::Y, block.size().y);
            }
        }
    }

    /// Cars on the street segment from `start` (on the centre line) `length_m` along `along`,
    /// in both directions; traffic keeps right.
    fn add_segment_cars(&mut self, start: Vec2, along: Vec2, length_m: f32) {
        let half_street = self.params.street_width_m * 0.5;
        let lanes = ((half_street / LANE_WIDTH_M).floor() as u32).max(1);
        let lane_width = half_street / lanes as f32;
        // Right of `along` in the ground plane, Y up: (x, z) -> (-z, x).
        let right = Vec2::new(-along.y, along.x);
        let slots = ((length_m - 2.0 * CAR_END_MARGIN_M) / CAR_SPACING_M)
            .floor()
            .max(0.0) as u32;
        for direction in [1.0, -1.0] {
            for lane in 0..lanes {
                let offset = right * direction * lane_width * (lane as f32 + 0.5);
                for slot in 0..slots {
                    if !self.rng.chance(CAR_CHANCE) {
                        continue;
                    }
                    let t = CAR_END_MARGIN_M
                        + (slot as f32 + 0.5) * CAR_SPACING_M
                        + self.rng.range_f32(-0.4, 0.4);
                    self.add_car(start + along * t + offset, along * direction);
                    self.add_car_motion(start, along, length_m, offset, direction, t);
                }
            }
        }
    }

    /// The last car drives on along its lane and wraps around within the segment (between the
    /// end margins). Its speed, 7 to 13 m/s, comes from its index, not the random stream, so
    /// the city's layout does not depend on it.
    fn add_car_motion(
        &mut self,
        start: Vec2,
        along: Vec2,
        length_m: f32,
        lateral: Vec2,
        direction: f32,
        t: f32,
    ) {
        let usable = (length_m - 2.0 * CAR_END_MARGIN_M).max(1.0);
        let (segment_start, heading, offset) = if direction > 0.0 {
            (
                start + along * CAR_END_MARGIN_M + lateral,
                along,
                t - CAR_END_MARGIN_M,
            )
        } else {
            (
                start + along * (length_m - CAR_END_MARGIN_M) + lateral,
                -along,
                length_m - CAR_END_MARGIN_M - t,
            )
        };
        let hash = (self.cars.wrapping_mul(2_654_435_761) >> 16) % 1000;
        self.motions.push(Motion {
            instance: self.instances.len() as u32 - 1,
            start: Vec3::new(segment_start.x, 0.0, segment_start.y),
            direction: Vec3::new(heading.x, 0.0, heading.y),
            length_m: usable,
            offset_m: offset,
            speed_m_per_s: 7.0 + 6.0 * hash as f32 / 1000.0,
        });
    }

    /// A car standing at `position`, its nose (local +x) along `heading`.
    fn add_car(&mut self, position: Vec2, heading: Vec2) {
        let u = self.rng.unit_f32();
        let kind = if u < 0.5 {
            Proto::Sedan
        } else if u < 0.85 {
            Proto::Suv
        } else {
            Proto::Truck
        };
        let color = self.pick_color(&CAR_PAINT);
        // Rotating by `yaw` about +Y takes +x to (cos yaw, 0, -sin yaw).
        let yaw = (-heading.y).atan2(heading.x);
        let world_from_local = Mat4::from_rotation_translation(
            Quat::from_rotation_y(yaw),
            Vec3::new(position.x, 0.0, position.y),
        );
        let name = format!("car_{}", self.cars);
        self.cars += 1;
        self.place(name, kind, world_from_local, color, Mobility::Dynamic);
    }
}
