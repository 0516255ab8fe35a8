//! The built-in city: a Manhattan-like grid of blocks separated by streets, each block a raised
//! sidewalk with buildings on lots cut from it, street trees along the kerb, a few towers, and
//! cars in the lanes. A handful of meshes are shared by every instance; an instance's transform
//! gives it its size. Everything follows from [`CityParams`], the seed included.
//!
//! Where things live: [`CityParams`] and [`RectXz`] in `params`, the shared meshes in `proto`,
//! the random stream in `rng`; this file walks the blocks, and `buildings`, `trees` and `cars`
//! place what stands on them. The order of random draws is the city's identity: a change in it
//! changes every city, so code that draws must keep its order when moved.

mod buildings;
mod cars;
mod lamps;
mod params;
mod proto;
mod rng;
mod trees;

use glam::{Mat4, Vec3};

use super::{Instance, Mesh, Mobility, Motion, Scene, Sun};
pub use lamps::street_lamps;
pub use params::{CityParams, RectXz};
use proto::Proto;
pub(super) use rng::SplitMix64;

// `tests.rs` reaches these through `super::*`.
#[cfg(test)]
use glam::Vec2;
#[cfg(test)]
use proto::building_profile;

/// Height of the sidewalk slab every block stands on, metres.
const KERB_HEIGHT_M: f32 = 0.15;
/// Sidewalk between the kerb and the lots, metres.
const SIDEWALK_WIDTH_M: f32 = 5.0;
const PARK_BLOCK_CHANCE: f32 = 0.04;
const POCKET_PARK_CHANCE: f32 = 0.05;
/// One tower per this many blocks, on the central blocks.
const BLOCKS_PER_TOWER: u32 = 20;

/// Linear RGB colours of the ground, the sidewalks and the parks.
const ASPHALT: [f32; 3] = [0.045, 0.045, 0.05];
const SIDEWALK: [f32; 3] = [0.33, 0.32, 0.30];
const GRASS: [f32; 3] = [0.07, 0.17, 0.04];

/// The city described by `params`, as scene `name`.
pub fn build_city(name: String, params: &CityParams) -> Scene {
    let mut city = CityBuilder {
        params,
        rng: SplitMix64::new(params.seed),
        meshes: Proto::ALL.iter().map(|proto| proto.mesh()).collect(),
        instances: Vec::new(),
        towers: 0,
        cars: 0,
        motions: Vec::new(),
    };
    city.add_ground_tiles();
    let tower_blocks = city.choose_tower_blocks();
    for j in 0..params.blocks_z {
        for i in 0..params.blocks_x {
            city.add_block(i, j, tower_blocks.contains(&(i, j)));
        }
    }
    city.add_cars();
    let mut scene = Scene::new(
        name,
        city.meshes,
        city.instances,
        Sun::from_azimuth_elevation_deg(35.0, 40.0),
    );
    scene.motions = city.motions;
    scene
}

struct CityBuilder<'a> {
    params: &'a CityParams,
    rng: SplitMix64,
    meshes: Vec<Mesh>,
    instances: Vec<Instance>,
    towers: u32,
    cars: u32,
    /// Each car drives along its lane: one motion per car.
    motions: Vec<Motion>,
}

/// Names the objects of one block: `block_3_7/building_2`, `block_3_7/tree_0`.
struct BlockNames {
    prefix: String,
    buildings: u32,
    trees: u32,
}

impl BlockNames {
    fn next(&mut self, kind: &str) -> String {
        let counter = if kind == "tree" {
            &mut self.trees
        } else {
            &mut self.buildings
        };
        *counter += 1;
        format!("{}/{kind}_{}", self.prefix, *counter - 1)
    }
}

impl CityBuilder<'_> {
    fn place(
        &mut self,
        name: String,
        proto: Proto,
        world_from_local: Mat4,
        color: [f32; 4],
        mobility: Mobility,
    ) {
        let mesh = &self.meshes[proto.id() as usize];
        let instance = Instance::new(name, proto.id(), mesh, world_from_local)
            .with_color(color)
            .with_mobility(mobility);
        self.instances.push(instance);
    }

    /// A palette colour, a little brighter or darker.
    fn pick_color(&mut self, palette: &[[f32; 3]]) -> [f32; 4] {
        let [r, g, b] = palette[self.rng.below(palette.len())];
        let shade = self.rng.range_f32(0.85, 1.15);
        [r * shade, g * shade, b * shade, 1.0]
    }

    fn add_ground_tiles(&mut self) {
        for j in 0..self.params.blocks_z {
            for i in 0..self.params.blocks_x {
                let tile = self.params.ground_tile_rect(i, j);
                let color = [ASPHALT[0], ASPHALT[1], ASPHALT[2], 1.0];
                self.place(
                    format!("ground_{i}_{j}"),
                    Proto::GroundTile,
                    slab_transform(tile, 1.0),
                    color,
                    Mobility::Static,
                );
            }
        }
    }

    /// Distinct blocks for the towers, from the central half of the grid.
    fn choose_tower_blocks(&mut self) -> Vec<(u32, u32)> {
        let (bx, bz) = (self.params.blocks_x, self.params.blocks_z);
        let mut candidates: Vec<(u32, u32)> = (bz / 4..bz - bz / 4)
            .flat_map(|j| (bx / 4..bx - bx / 4).map(move |i| (i, j)))
            .collect();
        let count = ((bx * bz / BLOCKS_PER_TOWER).max(1) as usize).min(candidates.len());
        for k in 0..count {
            let pick = k + self.rng.below(candidates.len() - k);
            candidates.swap(k, pick);
        }
        candidates.truncate(count);
        candidates
    }

    fn add_block(&mut self, i: u32, j: u32, has_tower: bool) {
        let mut names = BlockNames {
            prefix: format!("block_{i}_{j}"),
            buildings: 0,
            trees: 0,
        };
        let block = self.params.block_rect(i, j);
        let is_park = !has_tower && self.rng.chance(PARK_BLOCK_CHANCE);
        let slab_color = if is_park { GRASS } else { SIDEWALK };
        let color = [slab_color[0], slab_color[1], slab_color[2], 1.0];
        let name = format!(
            "{}/{}",
            names.prefix,
            if is_park { "park" } else { "sidewalk" }
        );
        self.place(
            name,
            Proto::Sidewalk,
            slab_transform(block, KERB_HEIGHT_M),
            color,
            Mobility::Static,
        );
        self.add_street_trees(&mut names, block);

        let lots_area = block.shrunk(SIDEWALK_WIDTH_M);
        if has_tower {
            self.add_tower(lots_area);
        } else if is_park {
            self.add_trees_in(&mut names, lots_area, 10.0, 0.75);
        } else {
            for lot in self.cut_lots(lots_area) {
                if self.rng.chance(POCKET_PARK_CHANCE) {
                    self.add_trees_in(&mut names, lot, 7.0, 0.9);
                } else {
                    self.add_building(&mut names, lot);
                }
            }
        }
    }
}

/// Scales a unit-footprint mesh (x, z in `[-0.5, 0.5]`, y in `[0, 1]`) to `rect`, `height` tall.
fn slab_transform(rect: RectXz, height: f32) -> Mat4 {
    let center = rect.center();
    let size = rect.size();
    Mat4::from_translation(Vec3::new(center.x, 0.0, center.y))
        * Mat4::from_scale(Vec3::new(size.x, height, size.y))
}

#[cfg(test)]
mod tests;
