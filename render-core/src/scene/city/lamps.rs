//! Street lamps of the city at night (`builtin:city-night`, the many-lights issue's larger
//! case): a spot light over each street crossing of the middle of the city, shining down.

use glam::{Vec2, Vec3};

use super::CityParams;
use crate::scene::{LightKind, PunctualLight, Sun};

/// Crossings with a lamp, along x and along z, centred on the city's middle.
const LAMPS_X: u32 = 8;
const LAMPS_Z: u32 = 6;
/// A lamp's height over the crossing, metres.
const LAMP_HEIGHT_M: f32 = 9.0;
const OUTER_CONE_DEG: f32 = 68.0;
const INNER_CONE_DEG: f32 = 50.0;
const RANGE_M: f32 = 40.0;
/// Sodium orange, linear RGB.
const SODIUM: [f32; 3] = [1.0, 0.72, 0.42];
/// Under a lamp the street gets half the sun's illuminance ([`Sun::ILLUMINANCE_LX`]).
const INTENSITY_CD: f32 = Sun::ILLUMINANCE_LX / 2.0 * LAMP_HEIGHT_M * LAMP_HEIGHT_M;

/// The lamps over the crossings of the middle `LAMPS_X` x `LAMPS_Z` streets (fewer in a
/// smaller city), named `lamp_I_J` by crossing.
pub fn street_lamps(params: &CityParams) -> Vec<PunctualLight> {
    let ground = params.ground_rect();
    let pitch = params.pitch_m();
    let half_street = Vec2::splat(params.street_width_m * 0.5);
    let (nx, nz) = (params.blocks_x + 1, params.blocks_z + 1);
    let (lx, lz) = (LAMPS_X.min(nx), LAMPS_Z.min(nz));
    let (first_x, first_z) = ((nx - lx) / 2, (nz - lz) / 2);
    let mut lamps = Vec::new();
    for j in first_z..first_z + lz {
        for i in first_x..first_x + lx {
            let at = ground.min + half_street + pitch * Vec2::new(i as f32, j as f32);
            lamps.push(PunctualLight {
                name: format!("lamp_{i}_{j}"),
                position: Vec3::new(at.x, LAMP_HEIGHT_M, at.y),
                kind: LightKind::Spot {
                    direction: Vec3::NEG_Y,
                    inner_cone_rad: INNER_CONE_DEG.to_radians(),
                    outer_cone_rad: OUTER_CONE_DEG.to_radians(),
                },
                color: SODIUM,
                intensity: INTENSITY_CD,
                range: Some(RANGE_M),
            });
        }
    }
    lamps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forty_eight_lamps_hang_over_street_crossings_of_the_middle_of_the_city() {
        let params = CityParams::full(0);
        let lamps = street_lamps(&params);
        assert_eq!(lamps.len(), 48);
        let ground = params.ground_rect();
        for lamp in &lamps {
            let p = lamp.position;
            assert!(p.x > ground.min.x && p.x < ground.max.x && p.z > ground.min.y);
            // A crossing: on no block.
            let on_block = (0..params.blocks_x).any(|i| {
                (0..params.blocks_z).any(|j| {
                    let b = params.block_rect(i, j);
                    p.x > b.min.x && p.x < b.max.x && p.z > b.min.y && p.z < b.max.y
                })
            });
            assert!(!on_block, "{} stands over a block", lamp.name);
        }
        // Centred: as many lamps either side of the middle, within a street pitch.
        let mean: Vec3 = lamps.iter().map(|l| l.position).sum::<Vec3>() / 48.0;
        assert!(mean.x.abs() < params.pitch_m().x && mean.z.abs() < params.pitch_m().y);
        assert_eq!(street_lamps(&CityParams::small(0)).len(), 25);
    }
}
