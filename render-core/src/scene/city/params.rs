//! What a city is generated from, and the rectangles of its ground, blocks and ground tiles.

use glam::Vec2;

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

    pub(super) fn pitch_m(&self) -> Vec2 {
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
    pub(super) fn ground_tile_rect(&self, i: u32, j: u32) -> RectXz {
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
