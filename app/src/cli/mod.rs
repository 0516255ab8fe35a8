//! The command-line contract of DESIGN.md: arguments shared by `shot`, `bench` and the window.

use anyhow::{Context as _, bail};
use clap::{Args, Parser, Subcommand};
use glam::Vec3;
use render_core::cascades::{
    CascadeDepths, CascadeFit, CascadeSelection, MAX_CASCADES, SplitScheme,
};
use render_core::frame::{FrameSettings, Method, PcfKernel, ShadowSetup};
use render_core::geom::Camera;
use render_core::scene::{ChunkSettings, Scene, Sun, Units};

use crate::scene_source::{LoadOptions, frame_scene};

mod commands;
mod layered;
mod light;
mod virtual_maps;
mod volumes;

pub use commands::{BenchArgs, CheckArgs, FaultDrill, OpenArgs, ReportArgs, ShotArgs, Sweep};

#[derive(Parser, Debug)]
#[command(
    name = "shadowlab",
    version,
    about = "A lab for real-time shadows: open a scene, switch methods, measure."
)]
#[command(args_conflicts_with_subcommands = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub open: OpenArgs,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render one frame headless and write a PNG and a stats JSON.
    Shot(Box<ShotArgs>),
    /// Fly a camera path and print a table of methods (median over frames, after warm-up).
    Bench(Box<BenchArgs>),
    /// Run every technique family along a camera path and write a report folder.
    Report(Box<ReportArgs>),
    /// The hard cases (grazing and zenith sun, camera inside geometry, into the sun, empty
    /// view, 100 km out) with every technique: pass or fail with figures, and the exit status.
    Check(Box<CheckArgs>),
    /// List the built-in scenes.
    Scenes,
}

#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// builtin:NAME or a path to a .gltf / .glb file (`shadowlab scenes` lists the built-ins).
    /// Default: builtin:city; the window reopens the last scene it showed.
    #[arg(value_name = "SCENE")]
    pub scene: Option<String>,
    /// Seed of built-in scenes.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Split objects larger than this fraction of the scene into chunks (0 disables).
    #[arg(long, value_name = "FRACTION", default_value_t = ChunkSettings::default().max_extent_fraction)]
    pub chunk_fraction: f32,
    /// The unit of a glTF file's coordinates: m, cm, mm, in (the scene is scaled to metres).
    #[arg(long, value_name = "UNIT", default_value = "m", value_parser = parse_units)]
    pub units: Units,
    /// Every object this many times in its place, 1 to 16: the same shadows from that many
    /// times the geometry (Rákos's Figure 19.7 instances the scene four times).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub copies: u32,
}

/// The scene when none is named.
pub const DEFAULT_SCENE: &str = "builtin:city";

impl SceneArgs {
    /// The scene named on the command line, or [`DEFAULT_SCENE`].
    pub fn spec(&self) -> &str {
        self.scene.as_deref().unwrap_or(DEFAULT_SCENE)
    }

    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            seed: self.seed,
            chunking: ChunkSettings {
                max_extent_fraction: self.chunk_fraction,
            },
            units: self.units,
            copies: self.copies,
        }
    }
}

fn parse_units(s: &str) -> Result<Units, String> {
    s.parse()
}

/// Camera, sun and shadow settings of a frame.
#[derive(Args, Debug, Clone, Default)]
pub struct ViewArgs {
    /// Camera position x,y,z in metres.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<Vec3>,
    /// Point the camera looks at, x,y,z in metres.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target: Option<Vec3>,
    /// The scene's up, x,y,z, which the picture's up follows (default 0,1,0, glTF's).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub up: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(long, value_name = "DEG")]
    pub fov: Option<f32>,
    /// Near plane distance in metres.
    #[arg(long, value_name = "N")]
    pub near: Option<f32>,
    /// Far plane distance in metres.
    #[arg(long, value_name = "F")]
    pub far: Option<f32>,
    /// Direction from the scene towards the sun, x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub sun: Option<Vec3>,
    /// The light that casts the shadows (volumes, virtual maps): `sun`, `point` (the scene's
    /// first light, a spot in its cone; `point:N` its Nth, from 0), `spot` (`spot:N`: spots).
    #[arg(long, value_parser = light::parse_light, value_name = "LIGHT")]
    pub light: Option<light::LightArg>,
    /// Image size `WIDTHxHEIGHT` in pixels.
    #[arg(long, value_parser = parse_size, value_name = "WxH")]
    pub size: Option<(u32, u32)>,
    /// Shadow map resolution in texels (512 to 8192; each light's map with `--shadow lights`,
    /// 64 to 4096).
    #[arg(long, value_name = "N")]
    pub shadow_res: Option<u32>,
    /// Shadow caster method.
    #[arg(long, value_parser = parse_method, value_name = "NAME")]
    pub method: Option<Method>,
    /// Which shadow view (cascade) the light-view inset shows, from 0.
    #[arg(long, value_name = "N")]
    pub inset_view: Option<u32>,
    /// Overlay to draw (repeatable): light-view, error, casters, cascades, fill (shadow-volume
    /// fill heat map), volumes (the shadow volumes, translucent).
    #[arg(long, value_name = "NAME")]
    pub overlay: Vec<String>,
    /// PCF kernel: off, 2x2, 3x3, 5x5.
    #[arg(long, value_parser = parse_pcf, value_name = "KERNEL")]
    pub pcf: Option<PcfKernel>,
    /// Constant depth bias in metres.
    #[arg(long, value_name = "M")]
    pub depth_bias: Option<f32>,
    /// More constant depth bias, in texels of each shadow view (so it grows with a cascade's
    /// texel size).
    #[arg(long, value_name = "TEXELS")]
    pub depth_bias_texels: Option<f32>,
    /// Slope-scaled bias, in texels of depth slope.
    #[arg(long, value_name = "S")]
    pub slope_bias: Option<f32>,
    /// Normal offset, in shadow texels.
    #[arg(long, value_name = "TEXELS")]
    pub normal_offset: Option<f32>,
    /// Shadow setup: single (one map), lispsm (one map warped in light space), cascades,
    /// volumes (stencil shadow volumes, no map), lights (the scene's lamps, a map each), or
    /// virtual (virtual shadow maps: a clipmap of cached pages).
    #[arg(long, value_parser = parse_setup, value_name = "SETUP")]
    pub shadow: Option<ShadowSetup>,
    /// Number of cascades, 1 to 8 (with --shadow cascades).
    #[arg(long, value_name = "N")]
    pub cascades: Option<u32>,
    /// How the view is split into cascades: uniform, logarithmic, practical, geometric,
    /// manual.
    #[arg(long, value_parser = parse_split, value_name = "SCHEME")]
    pub split: Option<SplitScheme>,
    /// The practical split's logarithmic share, 0 to 1.
    #[arg(long, value_name = "L")]
    pub lambda: Option<f32>,
    /// The geometric split: where the first cascade ends, metres.
    #[arg(long, value_name = "M")]
    pub split_first: Option<f32>,
    /// The geometric split: each far distance over the one before.
    #[arg(long, value_name = "R")]
    pub split_ratio: Option<f32>,
    /// The manual split's distances between cascades, metres, increasing: d1,d2,...
    #[arg(long, value_name = "D1,D2,...")]
    pub splits: Option<String>,
    /// `--shadow volumes`: how far each volume reaches along the light: none (past the scene),
    /// continuous (across the visible receiver points under it, Lloyd's clamping), discrete
    /// (per slice of the view, an image-precision test), conservative (discrete, never
    /// losing an occupied interval), exact (the limit, Lloyd's exact clamping: each caster's own
    /// shadowed points by rays on the CPU, seconds per frame) or boxes (Lloyd's continuous
    /// clamping at object precision: receivers' boxes by sweep-and-prune on the CPU; the sun).
    #[arg(long, value_parser = volumes::parse_volume_clamp, value_name = "CLAMP")]
    pub volume_clamp: Option<render_core::volumes::VolumeClamp>,
    /// `--shadow volumes`: how the stencil counts each volume: auto (z-pass where the camera's
    /// near rectangle cannot lie in it, else z-fail with caps, as DOOM 3 does), z-pass or
    /// z-fail for every volume.
    #[arg(long, value_parser = volumes::parse_volume_pass, value_name = "PASS")]
    pub volume_pass: Option<render_core::volumes::VolumePassChoice>,
    /// Lloyd's V > R rule for clamped volumes: gap pixels a new interval's vertex is worth
    /// (default: measured on this device at start-up; 0 splits at every gap dearer than its
    /// caps).
    #[arg(long, value_name = "PIXELS")]
    pub volume_vertex_pixels: Option<u32>,
    /// Loop iterations a lane of the shadow volumes' cull may spend on one caster before
    /// workgroups of its own take it (default: the adapter's, 512 on a GPU; on a
    /// CPU adapter at most 6,991).
    #[arg(long, value_name = "N")]
    pub volume_cull_steps: Option<u32>,
    /// The most receiver points of one grid cell the shadow volumes' cull tests one by one
    /// against a caster; a cell with more gives its depths whole (default: 16 on a GPU,
    /// every point on a CPU adapter).
    #[arg(long, value_name = "N")]
    pub volume_cell_points: Option<u32>,
    /// Lanes that share one caster's cells and points in the shadow volumes' cull, 1 to 32
    /// (default: 32 on a GPU, 4 on a CPU adapter).
    #[arg(long, value_name = "N")]
    pub volume_cull_lanes: Option<u32>,
    /// Draw each clamped interval across the whole picture, not only across the strips of
    /// the view its receivers lie in (discrete clamping's slices; to measure their share).
    #[arg(long)]
    pub no_volume_strips: bool,
    /// `--volume-clamp discrete|conservative`: the view's slices (Lloyd's K), 1 to 32.
    #[arg(long, value_name = "K")]
    pub volume_slices: Option<u32>,
    /// `--shadow lispsm`: multiplies the warp's optimal n (Wimmer et al. 2004); below 1 warps
    /// harder, above 1 tends to a uniform map.
    #[arg(long, value_name = "SCALE")]
    pub lispsm_n: Option<f32>,
    /// How each cascade is fitted: tight (the slice's light-space box) or sphere (stabilised:
    /// texel-snapped, its slices measured as distances from the eye).
    #[arg(long, value_parser = parse_cascade_fit, value_name = "FIT")]
    pub cascade_fit: Option<CascadeFit>,
    /// Which cascade shades a point: depth (the slice holding its depth: view depth, or
    /// distance from the eye with the sphere fit) or map (the first cascade whose map holds it).
    #[arg(long, value_parser = parse_cascade_selection, value_name = "BY")]
    pub cascade_select: Option<CascadeSelection>,
    /// Which view depths the cascades split: scene (where the view meets the scene) or
    /// visible (the nearest to the furthest visible receiver pixel, as SDSM).
    #[arg(long, value_parser = parse_cascade_depths, value_name = "D")]
    pub cascade_depths: Option<CascadeDepths>,
    /// The share of each cascade's depths, at its far end, over which it blends into the next
    /// (the last fades out), 0 to 0.5 (with --cascade-select depth).
    #[arg(long, value_name = "F")]
    pub cascade_blend: Option<f32>,
    #[command(flatten)]
    pub lights: layered::LayeredArgs,
    #[command(flatten)]
    pub virtual_maps: virtual_maps::VirtualArgs,
    /// Pose dynamic objects (the city's cars) as they are this many seconds into their motion.
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    pub time: Option<f64>,
}

pub const DEFAULT_SIZE: (u32, u32) = (1280, 720);
pub const DEFAULT_FOV_DEG: f32 = 60.0;

impl ViewArgs {
    /// The frame settings these arguments ask for, starting from the scene's sun.
    pub fn settings(&self, scene: &Scene) -> anyhow::Result<FrameSettings> {
        let mut settings = self.settings_over(&FrameSettings {
            sun: scene.sun,
            ..FrameSettings::default()
        })?;
        self.light_over(&mut settings, scene)?;
        Ok(settings)
    }

    /// `base` with what these arguments set changed.
    pub fn settings_over(&self, base: &FrameSettings) -> anyhow::Result<FrameSettings> {
        let mut settings = *base;
        if let Some(sun) = self.sun {
            if sun.length_squared() == 0.0 || !sun.is_finite() {
                bail!("--sun must be a non-zero direction x,y,z, got {sun}");
            }
            settings.sun = Sun::from_direction(sun);
        }
        if let Some(res) = self.shadow_res {
            let range = layered::resolution_range(self.lights.asks_for_lights(self.shadow));
            if !range.contains(&res) {
                bail!(
                    "--shadow-res {res} is outside {} to {}",
                    range.start(),
                    range.end()
                );
            }
            settings.shadow.resolution = res;
        }
        if let Some(method) = self.method {
            settings.method = method;
        }
        if let Some(pcf) = self.pcf {
            settings.shadow.pcf = pcf;
        }
        for (value, name) in [
            (self.depth_bias, "--depth-bias"),
            (self.depth_bias_texels, "--depth-bias-texels"),
            (self.slope_bias, "--slope-bias"),
            (self.normal_offset, "--normal-offset"),
        ] {
            if value.is_some_and(|v| !v.is_finite() || v < 0.0) {
                bail!("{name} must be a finite number >= 0");
            }
        }
        settings.shadow.depth_bias_m = self.depth_bias.unwrap_or(settings.shadow.depth_bias_m);
        settings.shadow.depth_bias_texels = self
            .depth_bias_texels
            .unwrap_or(settings.shadow.depth_bias_texels);
        settings.shadow.slope_bias = self.slope_bias.unwrap_or(settings.shadow.slope_bias);
        settings.shadow.normal_offset_texels = self
            .normal_offset
            .unwrap_or(settings.shadow.normal_offset_texels);
        if let Some(view) = self.inset_view {
            settings.overlays.inset_view = view;
        }
        for name in &self.overlay {
            settings.overlays.enable(name).map_err(anyhow::Error::msg)?;
        }
        self.cascade_settings(&mut settings)?;
        self.virtual_maps.apply_to(self.shadow, &mut settings)?;
        Ok(settings)
    }

    /// The setup and the cascades' flags over `settings`.
    fn cascade_settings(&self, settings: &mut FrameSettings) -> anyhow::Result<()> {
        let cascades = &mut settings.cascades;
        if let Some(setup) = self.shadow {
            settings.setup = setup;
        }
        if let Some(count) = self.cascades {
            if !(1..=MAX_CASCADES).contains(&count) {
                bail!("--cascades {count} is outside 1 to {MAX_CASCADES}");
            }
            cascades.count = count;
        }
        if let Some(scheme) = self.split {
            cascades.splits.scheme = scheme;
        }
        if let Some(lambda) = self.lambda {
            if !(0.0..=1.0).contains(&lambda) {
                bail!("--lambda {lambda} is outside 0 to 1");
            }
            cascades.splits.lambda = lambda;
        }
        if let Some(first) = self.split_first {
            if !(first.is_finite() && first > 0.0) {
                bail!("--split-first must be a distance above 0 metres");
            }
            cascades.splits.first_m = first;
        }
        if let Some(ratio) = self.split_ratio {
            if !(ratio.is_finite() && ratio >= 1.0) {
                bail!("--split-ratio must be at least 1");
            }
            cascades.splits.ratio = ratio;
        }
        if let Some(list) = &self.splits {
            let distances = list
                .split(',')
                .map(|d| d.trim().parse::<f32>())
                .collect::<Result<Vec<_>, _>>()
                .ok()
                .filter(|d| d.iter().all(|d| d.is_finite() && *d > 0.0))
                .filter(|d| d.windows(2).all(|w| w[0] < w[1]))
                .with_context(|| {
                    format!("--splits '{list}': give increasing distances in metres, d1,d2,...")
                })?;
            if distances.len() > cascades.splits.manual_m.len() {
                bail!(
                    "--splits gives {} distances; 8 cascades need at most 7",
                    distances.len()
                );
            }
            cascades.splits.manual_m = [0.0; 7];
            cascades.splits.manual_m[..distances.len()].copy_from_slice(&distances);
            cascades.splits.scheme = SplitScheme::Manual;
        }
        if let Some(fit) = self.cascade_fit {
            cascades.fit = fit;
        }
        if let Some(selection) = self.cascade_select {
            cascades.selection = selection;
        }
        if let Some(depths) = self.cascade_depths {
            cascades.depths = depths;
        }
        if let Some(blend) = self.cascade_blend {
            if !(0.0..=0.5).contains(&blend) {
                bail!("--cascade-blend {blend} is outside 0 to 0.5");
            }
            cascades.blend = blend;
        }
        self.volumes_into(settings)?;
        self.lights.apply_to(self.shadow, settings)?;
        if let Some(scale) = self.lispsm_n {
            let ok = scale.is_finite() && (0.01..=100.0).contains(&scale);
            anyhow::ensure!(ok, "--lispsm-n {scale} is outside 0.01 to 100");
            settings.lispsm.n_scale = scale;
        }
        Ok(())
    }

    pub fn size(&self) -> anyhow::Result<(u32, u32)> {
        let (w, h) = self.size.unwrap_or(DEFAULT_SIZE);
        if w == 0 || h == 0 || w > 16384 || h > 16384 {
            bail!("--size {w}x{h}: width and height must be between 1 and 16384");
        }
        Ok((w, h))
    }

    /// The camera: `--eye`/`--target` where given, else a view framing the whole scene.
    pub fn camera(&self, scene: &Scene, aspect: f32) -> anyhow::Result<Camera> {
        let framed = frame_scene(&scene.bounds(), aspect, DEFAULT_FOV_DEG.to_radians());
        let eye = self.eye.unwrap_or(framed.eye);
        let target = self.target.unwrap_or_else(|| {
            if self.eye.is_some() {
                scene.bounds().center()
            } else {
                framed.eye + framed.forward
            }
        });
        if eye == target {
            bail!("--eye and --target are the same point {eye}");
        }
        let fov_deg = self.fov.unwrap_or(DEFAULT_FOV_DEG);
        if !(1.0..=170.0).contains(&fov_deg) {
            bail!("--fov {fov_deg} must be between 1 and 170 degrees");
        }
        let near = self.near.unwrap_or(framed.near_m);
        let far = self.far.unwrap_or(
            framed
                .far_m
                .max((eye - scene.bounds().center()).length() + scene.bounds().diagonal_length()),
        );
        if !(near > 0.0 && far > near) {
            bail!("--near {near} and --far {far}: need 0 < near < far");
        }
        let up = self.up.unwrap_or(Vec3::Y);
        if up.length_squared() == 0.0 || !up.is_finite() {
            bail!("--up {up} is not a direction");
        }
        Ok(Camera::look_at(eye, target, fov_deg.to_radians(), near, far).with_up(up))
    }
}

fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(format!("expected x,y,z, got '{s}'"));
    }
    let mut v = [0.0f32; 3];
    for (slot, part) in v.iter_mut().zip(parts) {
        *slot = part
            .trim()
            .parse()
            .map_err(|_| format!("'{part}' in '{s}' is not a number"))?;
        if !slot.is_finite() {
            return Err(format!("'{part}' in '{s}' is not finite"));
        }
    }
    Ok(Vec3::from_array(v))
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, got '{s}'"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{v}' in '{s}' is not a whole number"))
    };
    Ok((parse(w)?, parse(h)?))
}

fn parse_method(s: &str) -> Result<Method, String> {
    s.parse()
}

fn parse_pcf(s: &str) -> Result<PcfKernel, String> {
    s.parse()
}

fn parse_setup(s: &str) -> Result<ShadowSetup, String> {
    s.parse()
}

fn parse_split(s: &str) -> Result<SplitScheme, String> {
    s.parse()
}

fn parse_cascade_fit(s: &str) -> Result<CascadeFit, String> {
    s.parse()
}

fn parse_cascade_selection(s: &str) -> Result<CascadeSelection, String> {
    s.parse()
}

fn parse_cascade_depths(s: &str) -> Result<CascadeDepths, String> {
    s.parse()
}

/// `--methods m1,m2` or `all`.
pub fn parse_methods(list: &str) -> anyhow::Result<Vec<Method>> {
    if list == "all" {
        return Ok(Method::ALL.to_vec());
    }
    list.split(',')
        .map(|m| m.trim().parse::<Method>().map_err(anyhow::Error::msg))
        .collect::<anyhow::Result<_>>()
        .context("--methods")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_and_sizes_parse_or_name_the_problem() {
        assert_eq!(parse_vec3("1,-2.5, 3").unwrap(), Vec3::new(1.0, -2.5, 3.0));
        assert!(parse_vec3("1,2").unwrap_err().contains("x,y,z"));
        assert!(parse_vec3("1,a,3").unwrap_err().contains("'a'"));
        assert_eq!(parse_size("640x480").unwrap(), (640, 480));
        assert!(parse_size("640").is_err());
    }

    #[test]
    fn cli_accepts_the_documented_contract() {
        let cli = Cli::try_parse_from([
            "shadowlab",
            "shot",
            "builtin:boxes",
            "--out",
            "a.png",
            "--eye",
            "1,2,3",
            "--target",
            "0,0,0",
            "--fov",
            "50",
            "--near",
            "0.1",
            "--far",
            "500",
            "--sun",
            "0.3,1,-0.2",
            "--size",
            "320x200",
            "--shadow-res",
            "1024",
            "--method",
            "none",
            "--overlay",
            "light-view",
        ])
        .expect("documented flags parse");
        assert!(matches!(cli.command, Some(Command::Shot(_))));
        assert!(
            Cli::try_parse_from(["shadowlab", "shot", "--out", "a.png", "--method", "nope"])
                .is_err()
        );
        let open =
            Cli::try_parse_from(["shadowlab", "scene.glb"]).expect("a scene path opens the window");
        assert_eq!(open.open.scene.spec(), "scene.glb");
        assert!(parse_methods("none,bogus").is_err());
    }
}
