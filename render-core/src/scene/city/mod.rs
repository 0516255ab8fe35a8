//! The built-in city: a Manhattan-like grid of blocks separated by streets, each block a raised
//! sidewalk with buildings on lots cut from it, street trees along the kerb, a few towers, and
//! cars in the lanes. A handful of meshes are shared by every instance; an instance's transform
//! gives it its size. Everything follows from [`CityParams`], the seed included.

use std::f32::consts::TAU;

use glam::{Mat4, Quat, Vec2, Vec3};

use super::builtin::{MeshBuilder, SQUARE_RING, circle_ring, unit_ground_quad};
use super::{Instance, Mesh, MeshId, Mobility, Motion, Scene, Sun};

/// Height of the sidewalk slab every block stands on, metres.
const KERB_HEIGHT_M: f32 = 0.15;
/// Sidewalk between the kerb and the lots, metres.
const SIDEWALK_WIDTH_M: f32 = 5.0;
/// Street trees stand this far in from the kerb, at most this far apart.
const STREET_TREE_INSET_M: f32 = 2.3;
const STREET_TREE_SPACING_M: f32 = 12.0;
const STREET_TREE_CHANCE: f32 = 0.5;
/// Tree scale range; crowns are at most 1.9 m wide times the scale.
const TREE_SCALE: [f32; 2] = [0.8, 1.2];
/// Trees in parks keep this far from the park's edge, so their crowns stay inside it.
const TREE_CLEARANCE_M: f32 = 2.3;
/// Lots are cut until no side is longer than this.
const MAX_LOT_SIZE_M: f32 = 22.0;
/// Gap between a lot's edge and its building, per side, metres.
const LOT_MARGIN_M: [f32; 2] = [0.5, 1.5];
/// A building is at most this many times taller than its footprint is narrow.
const MAX_SLENDERNESS: f32 = 8.0;
const PARK_BLOCK_CHANCE: f32 = 0.04;
const POCKET_PARK_CHANCE: f32 = 0.05;
/// One tower per this many blocks, on the central blocks.
const BLOCKS_PER_TOWER: u32 = 20;
const MAX_TOWER_FOOTPRINT_M: f32 = 50.0;
const LANE_WIDTH_M: f32 = 4.0;
/// Cars keep this far from intersections and stand in slots this far apart.
const CAR_END_MARGIN_M: f32 = 2.0;
const CAR_SPACING_M: f32 = 7.5;
const CAR_CHANCE: f32 = 0.11;

/// Linear RGB palettes.
const ASPHALT: [f32; 3] = [0.045, 0.045, 0.05];
const SIDEWALK: [f32; 3] = [0.33, 0.32, 0.30];
const GRASS: [f32; 3] = [0.07, 0.17, 0.04];
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
const FOLIAGE: [[f32; 3]; 3] = [[0.05, 0.18, 0.04], [0.08, 0.22, 0.05], [0.10, 0.16, 0.03]];
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

/// What a city is generated from. Y is up, metres, the city centred on the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CityParams {
    pub blocks_x: u32,
    pub blocks_z: u32,
    /// Size of one block, kerb to kerb, along x and z.
    pub block_size_m: Vec2,
    pub street_width_m: f32,
    pub seed: u64,
}

impl CityParams {
    /// The `city` scene: 12 x 20 blocks of 100 m x 56 m, about 9,500 objects and 1.1M triangles.
    pub fn full(seed: u64) -> Self {
        Self {
            blocks_x: 12,
            blocks_z: 20,
            block_size_m: Vec2::new(100.0, 56.0),
            street_width_m: 16.0,
            seed,
        }
    }

    /// The `city-small` scene: the same blocks, 4 x 4 of them: a few hundred objects.
    pub fn small(seed: u64) -> Self {
        Self {
            blocks_x: 4,
            blocks_z: 4,
            ..Self::full(seed)
        }
    }

    fn pitch_m(&self) -> Vec2 {
        self.block_size_m + Vec2::splat(self.street_width_m)
    }

    /// The ground under the whole city, streets around the edge included.
    pub fn ground_rect(&self) -> RectXz {
        let blocks = Vec2::new(self.blocks_x as f32, self.blocks_z as f32);
        let half = (self.pitch_m() * blocks + Vec2::splat(self.street_width_m)) * 0.5;
        RectXz {
            min: -half,
            max: half,
        }
    }

    /// Block `(i, j)`, kerb to kerb.
    pub fn block_rect(&self, i: u32, j: u32) -> RectXz {
        let min = self.ground_rect().min
            + Vec2::splat(self.street_width_m)
            + self.pitch_m() * Vec2::new(i as f32, j as f32);
        RectXz {
            min,
            max: min + self.block_size_m,
        }
    }

    /// Ground tile `(i, j)`: block `(i, j)` and its streets out to their centre lines; tiles on
    /// the border reach the city's edge, so the tiles cover the ground without overlapping.
    fn ground_tile_rect(&self, i: u32, j: u32) -> RectXz {
        let (ground, block) = (self.ground_rect(), self.block_rect(i, j));
        let half_street = Vec2::splat(self.street_width_m * 0.5);
        let mut tile = RectXz {
            min: block.min - half_street,
            max: block.max + half_street,
        };
        if i == 0 {
            tile.min.x = ground.min.x;
        }
        if j == 0 {
            tile.min.y = ground.min.y;
        }
        if i + 1 == self.blocks_x {
            tile.max.x = ground.max.x;
        }
        if j + 1 == self.blocks_z {
            tile.max.y = ground.max.y;
        }
        tile
    }
}

/// A rectangle in the ground plane: `x` of the vectors is world x, `y` is world z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RectXz {
    pub min: Vec2,
    pub max: Vec2,
}

impl RectXz {
    pub fn size(&self) -> Vec2 {
        self.max - self.min
    }

    pub fn center(&self) -> Vec2 {
        (self.min + self.max) * 0.5
    }

    /// Moved in by `margin` on every side; a side too short for that shrinks to its middle.
    #[must_use]
    pub fn shrunk(&self, margin: f32) -> Self {
        let half = (self.size() * 0.5 - Vec2::splat(margin)).max(Vec2::ZERO);
        Self {
            min: self.center() - half,
            max: self.center() + half,
        }
    }
}

/// `SplitMix64` (Steele, Lea, Flood 2014): tiny, fast and good enough to lay out a city.
#[derive(Clone, Debug)]
pub(super) struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    pub(super) fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    pub(super) fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub(super) fn unit_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1_u64 << 24) as f32
    }

    pub(super) fn range_f32(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit_f32()
    }

    pub(super) fn chance(&mut self, probability: f32) -> bool {
        self.unit_f32() < probability
    }

    /// Uniform in `0..n`; 0 when `n` is 0.
    pub(super) fn below(&mut self, n: usize) -> usize {
        (((self.next_u64() >> 32) * n as u64) >> 32) as usize
    }
}

/// The shared meshes, in the order of [`Scene::meshes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Proto {
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
    const ALL: [Self; 11] = [
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

    fn id(self) -> MeshId {
        self as MeshId
    }

    fn mesh(self) -> Mesh {
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
fn building_profile(kind: Proto) -> Vec<[f32; 2]> {
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

    /// Cuts `area` in two across its longer side, again and again, until lots are small.
    fn cut_lots(&mut self, area: RectXz) -> Vec<RectXz> {
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

    fn add_building(&mut self, names: &mut BlockNames, lot: RectXz) {
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
    fn add_tower(&mut self, area: RectXz) {
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

    /// Trees along the kerb on every side of `block`, some slots left empty.
    fn add_street_trees(&mut self, names: &mut BlockNames, block: RectXz) {
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
    fn add_trees_in(&mut self, names: &mut BlockNames, area: RectXz, spacing_m: f32, chance: f32) {
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

    /// Cars on every street segment between two intersections, in every lane.
    fn add_cars(&mut self) {
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

/// Scales a unit-footprint mesh (x, z in `[-0.5, 0.5]`, y in `[0, 1]`) to `rect`, `height` tall.
fn slab_transform(rect: RectXz, height: f32) -> Mat4 {
    let center = rect.center();
    let size = rect.size();
    Mat4::from_translation(Vec3::new(center.x, 0.0, center.y))
        * Mat4::from_scale(Vec3::new(size.x, height, size.y))
}

#[cfg(test)]
mod tests;
