//! Buildings and towers: blocks are cut into lots, each lot gets a building whose height and kind
//! follow from where it stands, and a few central blocks get a tower instead.

use glam::{Mat4, Vec2, Vec3};

use super::{BlockNames, CityBuilder, KERB_HEIGHT_M, Mobility, Proto, RectXz, slab_transform};

/// Lots are cut until no side is longer than this.
const MAX_LOT_SIZE_M: f32 = 22.0;
/// Gap between a lot's edge and its building, per side, metres.
const LOT_MARGIN_M: [f32; 2] = [0.5, 1.5];
/// A building is at most this many times taller than its footprint is narrow.
const MAX_SLENDERNESS: f32 = 8.0;
const MAX_TOWER_FOOTPRINT_M: f32 = 50.0;

/// Linear RGB facade and tower glass colours.
const FACADES: [[f32; 3]; 7] = [
    [0.40, 0.39, 0.36],
    [0.56, 0.50, 0.40],
    [0.33, 0.12, 0.07],
    [0.22, 0.11, 0.06],
    [0.68, 0.67, 0.63],
    [0.10, 0.15, 0.22],
    [0.09, 0.09, 0.10],
];
const GLASS: [[f32; 3]; 3] = [[0.08, 0.13, 0.20], [0.15, 0.20, 0.24], [0.05, 0.07, 0.08]];

impl CityBuilder<'_> {
    /// Cuts `area` in two across its longer side, again and again, until lots are small.
    pub(super) fn cut_lots(&mut self, area: RectXz) -> Vec<RectXz> {
        let mut lots = Vec::new();
        let mut pending = vec![area];
        while let Some(lot) = pending.pop() {
            let size = lot.size();
            if size.max_element() <= MAX_LOT_SIZE_M {
                lots.push(lot);
                continue;
            }
            let t = self.rng.range_f32(0.35, 0.65);
            let (mut first, mut second) = (lot, lot);
            if size.x >= size.y {
                first.max.x = lot.min.x + size.x * t;
                second.min.x = first.max.x;
            } else {
                first.max.y = lot.min.y + size.y * t;
                second.min.y = first.max.y;
            }
            pending.extend([second, first]);
        }
        lots
    }

    pub(super) fn add_building(&mut self, names: &mut BlockNames, lot: RectXz) {
        let footprint = lot.shrunk(self.rng.range_f32(LOT_MARGIN_M[0], LOT_MARGIN_M[1]));
        let height_m = self
            .building_height_m(footprint.center())
            .min(MAX_SLENDERNESS * footprint.size().min_element());
        let u = self.rng.unit_f32();
        let kind = match height_m {
            h if h < 18.0 => {
                if u < 0.7 {
                    Proto::LowRise
                } else {
                    Proto::Plain
                }
            }
            h if h < 40.0 => {
                if u < 0.65 {
                    Proto::MidRise
                } else {
                    Proto::Plain
                }
            }
            _ if u < 0.6 => Proto::Setback,
            _ => Proto::MidRise,
        };
        let color = self.pick_color(&FACADES);
        let world_from_local =
            Mat4::from_translation(Vec3::Y * KERB_HEIGHT_M) * slab_transform(footprint, height_m);
        self.place(
            names.next("building"),
            kind,
            world_from_local,
            color,
            Mobility::Static,
        );
    }

    /// Mostly 10 m to 60 m, taller towards the middle of the city, now and then up to 90 m.
    fn building_height_m(&mut self, center: Vec2) -> f32 {
        if self.rng.chance(0.03) {
            return self.rng.range_f32(60.0, 90.0);
        }
        let half_size = self.params.ground_rect().size() * 0.5;
        let centrality = 1.0
            - (center / half_size.max(Vec2::ONE))
                .abs()
                .max_element()
                .min(1.0);
        let t = self.rng.unit_f32().powf(1.5) * (0.45 + 0.55 * centrality);
        10.0 + 50.0 * t
    }

    /// A tower of 100 m to 300 m in the middle of `area`.
    pub(super) fn add_tower(&mut self, area: RectXz) {
        let size =
            (area.size() * self.rng.range_f32(0.6, 0.85)).min(Vec2::splat(MAX_TOWER_FOOTPRINT_M));
        let footprint = RectXz {
            min: area.center() - size * 0.5,
            max: area.center() + size * 0.5,
        };
        let height_m = 100.0 + 200.0 * self.rng.unit_f32().powi(2);
        let color = self.pick_color(&GLASS);
        let world_from_local =
            Mat4::from_translation(Vec3::Y * KERB_HEIGHT_M) * slab_transform(footprint, height_m);
        let name = format!("tower_{}", self.towers);
        self.towers += 1;
        self.place(
            name,
            Proto::Tower,
            world_from_local,
            color,
            Mobility::Static,
        );
    }
}
