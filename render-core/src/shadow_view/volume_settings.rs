//! What a user sets about shadow volumes (`volumes/`), beside the shadow-map settings so the
//! frame and every technique can carry them.

/// How far each caster's volume reaches along the light.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum VolumeClamp {
    /// Past the scene's far side: the standard volume.
    None,
    /// Only across the depths of the visible receiver points under the caster's box in the
    /// light's view (Lloyd's continuous clamping, 3.2.1, one interval per caster): no volume
    /// crosses the empty space above or below the receivers.
    #[default]
    Continuous,
    /// The view cut into `slices` strips; per strip the receiver points under the box give
    /// an occupied interval, and the volume is drawn only across those (Lloyd's discrete
    /// clamping, 3.2.2): an image-precision test of the cells whose centres the box covers,
    /// which can lose an interval whose receivers lie near the box's edge.
    Discrete,
    /// Discrete clamping with every cell the box touches (Lloyd's conservative variant,
    /// 3.2.3): never loses an occupied interval.
    Conservative,
    /// The limit (Lloyd's `CCe`): per caster, the depths of the visible receiver points its
    /// own triangles shadow, by a ray from each point to the light on the CPU
    /// (`volumes/exact.rs`). Seconds per frame: a measure of what clamping could save.
    Exact,
    /// Lloyd's continuous clamping as the paper does it, at object precision: the depths of
    /// the boxes of the receivers in the camera's view that the caster's box overlaps across
    /// the light, by sweep-and-prune on the CPU (`volumes/box_clamp.rs`). The sun only:
    /// under a point light, `continuous`.
    Boxes,
}

impl VolumeClamp {
    pub const ALL: [Self; 6] = [
        Self::None,
        Self::Continuous,
        Self::Discrete,
        Self::Conservative,
        Self::Exact,
        Self::Boxes,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Continuous => "continuous",
            Self::Discrete => "discrete",
            Self::Conservative => "conservative",
            Self::Exact => "exact",
            Self::Boxes => "boxes",
        }
    }

    /// The strips of the view this clamping tells receivers apart by.
    pub fn slices(self, settings: &VolumeSettings) -> u32 {
        match self {
            Self::None | Self::Continuous | Self::Exact | Self::Boxes => 1,
            Self::Discrete | Self::Conservative => {
                settings.slices.clamp(1, VolumeSettings::MAX_SLICES)
            }
        }
    }
}

impl std::str::FromStr for VolumeClamp {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| {
                format!(
                    "unknown volume clamping '{s}' (available: none, continuous, discrete, \
                     conservative, exact, boxes)"
                )
            })
    }
}

/// How the stencil counts each caster's volume.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum VolumePassChoice {
    /// Per caster, as DOOM 3 chooses: z-pass where the camera's near rectangle cannot lie
    /// inside the volume, z-fail with caps where it can.
    #[default]
    Auto,
    /// Every volume z-pass (Heidmann): wrong where the near plane cuts a volume.
    ZPass,
    /// Every volume z-fail with caps (Carmack; Everitt and Kilgard).
    ZFail,
}

impl VolumePassChoice {
    pub const ALL: [Self; 3] = [Self::Auto, Self::ZPass, Self::ZFail];

    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::ZPass => "z-pass",
            Self::ZFail => "z-fail",
        }
    }
}

impl std::str::FromStr for VolumePassChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| format!("unknown volume pass '{s}' (available: auto, z-pass, z-fail)"))
    }
}

/// What a user sets about shadow volumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct VolumeSettings {
    pub clamp: VolumeClamp,
    pub pass: VolumePassChoice,
    /// Discrete clamping's strips of the view (Lloyd's K), 1 to [`Self::MAX_SLICES`].
    pub slices: u32,
    /// Lloyd's V > R rule: how many gap pixels a new interval's vertex is worth, or `None`
    /// for the cost measured on this device at start-up (`0`: split at every gap that
    /// costs more than its caps).
    pub vertex_pixels: Option<u32>,
    /// Loop iterations a lane of the cull may spend on one caster before workgroups of its
    /// own gather its receivers (`volumes/frame.rs` `StepBudget`), or `None` for the
    /// adapter's (512 on a GPU; on a CPU adapter, which silently ends long
    /// shader loops, at most 6,991 whatever is set).
    pub cull_steps: Option<u32>,
    /// The most receiver points of one grid cell the cull tests one by one against a
    /// caster (a cell with more gives its depths whole: less tight, much cheaper on a GPU
    /// near the camera, where a cell holds hundreds of pixels), or `None` for the
    /// adapter's (16 on a GPU, every point on a CPU adapter).
    pub cell_points: Option<u32>,
    /// Lanes of the cull's workgroup that share one caster's cells and points, 1 to 32, or
    /// `None` for the adapter's (32 on a GPU, 4 on a CPU adapter).
    pub cull_lanes: Option<u32>,
    /// Discrete clamping draws each interval only across the strips of the picture its
    /// receivers lie in, clipped at Lloyd's slicing planes through the eye (where the adapter
    /// has clip distances); off, across the whole picture, to measure what the strips save.
    pub strips: bool,
}

impl VolumeSettings {
    pub const MAX_SLICES: u32 = 32;
}

impl Default for VolumeSettings {
    fn default() -> Self {
        Self {
            clamp: VolumeClamp::default(),
            pass: VolumePassChoice::default(),
            slices: 8,
            vertex_pixels: None,
            cull_steps: None,
            cell_points: None,
            cull_lanes: None,
            strips: true,
        }
    }
}
