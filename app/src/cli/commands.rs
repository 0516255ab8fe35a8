//! Each command's own flags: the window's, and the headless `shot`, `bench`, `report` and
//! `check`.

use std::path::PathBuf;

use clap::Args;
use glam::Vec3;

use super::{SceneArgs, ViewArgs, parse_vec3};

/// `shadowlab shot`.
#[derive(Args, Debug)]
pub struct ShotArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    /// PNG to write.
    #[arg(long, value_name = "PNG")]
    pub out: PathBuf,
    /// Loses the GPU device before the frame, to test the message (hidden: a test's aid).
    #[arg(long, hide = true, value_name = "FAULT")]
    pub fault_drill: Option<FaultDrill>,
    /// Stats JSON to write (default: the PNG's name with .json).
    #[arg(long, value_name = "JSON")]
    pub stats: Option<PathBuf>,
    /// Add `objects_detail` to the stats: per object its name, whether it is visible, what
    /// happened to it in the shadow pass, and whether it is in the oracle set.
    #[arg(long)]
    pub detail: bool,
    /// Leave the overlays' legend out of the picture (drawn over its bottom-left corner
    /// whenever an overlay is on, as in the window).
    #[arg(long)]
    pub no_legend: bool,
    /// Observer camera: render the view (and its stats), then picture it from this point,
    /// x,y,z, with its frustum, cascade ends and light boxes drawn as lines.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub observe_from: Option<Vec3>,
    /// Where the observer looks (default: 40 m ahead of the view's eye).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, value_name = "X,Y,Z", requires = "observe_from")]
    pub observe_target: Option<Vec3>,
    /// Skip the exact shadow (a ray per pixel on the CPU, then one towards the sun) and the
    /// `exact_error` it gives in the stats.
    #[arg(long)]
    pub no_truth: bool,
    /// Also measure flicker: render the view moved 1 cm and turned 0.1 degrees and count the
    /// pixels whose shadow changes at the first view's surface points (`flicker` in the stats).
    #[arg(long)]
    pub flicker: bool,
}

/// `shadowlab bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Measured frames along the path.
    #[arg(long, default_value_t = 60, value_name = "N")]
    pub frames: u32,
    /// Frames rendered before measuring (pipelines compile, caches warm).
    #[arg(long, default_value_t = 5, value_name = "N")]
    pub warmup: u32,
    /// Skip the exact shadow (a ray per pixel on the CPU for each measured view; cached, so
    /// every method shares it) and the `exact err` columns.
    #[arg(long)]
    pub no_truth: bool,
    /// Also measure flicker on each measured frame (three more frames: the view, moved 1 cm,
    /// turned 0.1 degrees), the worst frame in the `flicker move/turn` column.
    #[arg(long)]
    pub flicker: bool,
    /// The sun turns about the up axis this many degrees a second (1/30 s a frame): the
    /// worst case for the virtual maps' cache (UE's moving-sun emulation).
    #[arg(long, value_name = "DEG_PER_S", allow_hyphen_values = true)]
    pub moving_sun: Option<f32>,
    /// Camera path CSV (`eye_x,eye_y,eye_z,target_x,target_y,target_z` per line); default: the
    /// scene's street path or an orbit.
    #[arg(long, value_name = "P")]
    pub path: Option<PathBuf>,
    /// Fly the path from its start at this speed, metres a second (1/30 s a frame, the clock
    /// of `--animate` and `--moving-sun`; the window plays paths at 15): the measured frames
    /// cover frames x speed / 30 metres of it. Without it they spread over the whole path,
    /// however long.
    #[arg(long, value_parser = parse_speed, value_name = "M_PER_S")]
    pub speed: Option<f32>,
    /// Methods to compare: comma list or `all`.
    #[arg(long, default_value = "all", value_name = "m1,m2")]
    pub methods: String,
    /// Also write the table as CSV.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Also draw the sweep as a PNG. `--sweep maps`: Rákos's figures, per map size the maps'
    /// GPU time and the CPU time of recording them against the number of maps, a line per
    /// path and culling. `--sweep slices`: Lloyd's Figure 9, the GPU time standard volumes
    /// take and per method the stencil pass, the cull and clamp, and the time saved against
    /// the slices.
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
    /// Also print each method's GPU time per pass, with the culling's steps inside it
    #[arg(long)]
    pub passes: bool,
    /// Cars drive: each view is the scene 1/30 s after the one before (from `--time`, the
    /// same poses for every method), rendered once it has moved, without settling. How the
    /// incremental updates (`incr`) are measured.
    #[arg(long)]
    pub animate: bool,
    /// Speed-up is this method's GPU frame time over each method's (the first method run when
    /// this one is not among them).
    #[arg(long, default_value = "ref", value_name = "METHOD")]
    pub baseline: String,
    /// Repeat the table for several shadow-map sizes, sun elevations, cascade counts (after
    /// the single map), split schemes, practical-split lambdas, shadow setups or shadow-volume
    /// clampings.
    #[arg(long, value_enum)]
    pub sweep: Option<Sweep>,
    /// Shadow-map sizes of `--sweep resolution`.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1024,2048,4096",
        value_name = "N,N"
    )]
    pub resolutions: Vec<u32>,
    /// Sun elevations in degrees of `--sweep elevation` (azimuth stays the scene's).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "10,20,30,40,50,60,70,80",
        value_name = "DEG,DEG"
    )]
    pub elevations: Vec<f32>,
    /// Cascade counts of `--sweep cascades`.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1,2,4,8",
        value_name = "N,N"
    )]
    pub cascade_counts: Vec<u32>,
    /// Lambdas of `--sweep lambda`.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0,0.25,0.5,0.75,1",
        value_name = "L,L"
    )]
    pub lambdas: Vec<f32>,
    /// Blocks per side of `--sweep objects`: the city on N x N blocks (`builtin:city:N`, about
    /// 40 objects a block), 2 to 64.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "5,10,20,35,50",
        value_name = "N,N"
    )]
    pub city_blocks: Vec<u32>,
    /// Numbers of lights of `--sweep maps` (the scene's first N; a point light has six maps).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1,2,4,8,16,32",
        value_name = "N,N"
    )]
    pub light_counts: Vec<u32>,
    /// Map sizes of `--sweep maps` (default: `--shadow-res`), 64 to 4096 texels.
    #[arg(long, value_delimiter = ',', value_name = "N,N")]
    pub map_sizes: Vec<u32>,
    /// Per-layer culling of `--sweep maps`: none, frustum, back-faces, both (Rákos's
    /// Figures 19.8 and 19.9).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "none,both",
        value_name = "C,C"
    )]
    pub layer_cullings: Vec<String>,
    /// The paths of `--sweep maps`: traditional, multiview, atlas.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "traditional,multiview,atlas",
        value_name = "P,P"
    )]
    pub layered_paths: Vec<String>,
}

/// What `bench --sweep` varies.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sweep {
    /// Shadow-map resolution, as in Bittner's Table 4.
    Resolution,
    /// Sun elevation, as in Bittner's Figure 7.
    Elevation,
    /// The single map, the LiSPSM map, then cascades of each of `--cascade-counts`.
    Cascades,
    /// Every split scheme but manual, with the cascades of the other flags.
    Splits,
    /// The practical split's lambda, over `--lambdas`.
    Lambda,
    /// Every shadow setup (single, lispsm, cascades, volumes, lights, virtual), with the other
    /// flags.
    Setups,
    /// The virtual maps' goals in one run: a single map of 8192, 4 cascades of 2048 (the
    /// pool's memory; with `--light point`, shadow volumes instead), then the virtual maps with
    /// the cache on and off, the receiver mask and static casters apart.
    Virtual,
    /// Shadow volumes with each clamping (none, continuous, discrete, conservative).
    Clamp,
    /// Standard shadow volumes, then conservative discrete clamping over 1, 2, 4, 8, 16 and
    /// 32 slices against them (Lloyd's Figure 9); `--volume-clamp discrete` for the
    /// image-precision test.
    Slices,
    /// Many lights (Rákos's figures): every path (traditional, multiview, atlas) for each of
    /// `--light-counts` and `--map-sizes`, a row each with its passes, draws and CPU time.
    Maps,
    /// The city on each of `--city-blocks` N x N blocks (`builtin:city:N`): the methods'
    /// culling time, CPU and GPU, and shadow pass against the number of objects.
    Objects,
}

/// `shadowlab report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Folder to write: index.html, report.md, rows.csv, rows.json and the plots.
    #[arg(long, default_value = "report", value_name = "DIR")]
    pub out: PathBuf,
    /// Technique families: a comma list of culling, setups, volumes, lights, or `all` (the
    /// many-lights family only where the scene has lights).
    #[arg(long, default_value = "all", value_name = "f1,f2")]
    pub families: String,
    /// Measured frames along the path for every row.
    #[arg(long, default_value_t = 12, value_name = "N")]
    pub frames: u32,
    /// Frames rendered before measuring each row.
    #[arg(long, default_value_t = 3, value_name = "N")]
    pub warmup: u32,
    /// Camera path CSV, as `bench --path`; default: the scene's street path or an orbit.
    #[arg(long, value_name = "P")]
    pub path: Option<PathBuf>,
    /// Skip the exact shadow: error is then counted against the reference maps only.
    #[arg(long)]
    pub no_truth: bool,
    /// The sweeps of the papers' figures, each in its family's section: a comma list of
    /// resolution, elevation (culling), cascades, splits (setups), slices (volumes), maps
    /// (lights), or `all` or `none`.
    #[arg(long, default_value = "all", value_name = "s1,s2")]
    pub sweeps: String,
    /// Measured frames along the path for each row of a sweep (a sweep has many rows).
    #[arg(long, default_value_t = 4, value_name = "N")]
    pub sweep_frames: u32,
}

/// `shadowlab check`.
#[derive(Args, Debug)]
pub struct CheckArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Skip the exact shadow (shadow volumes are then checked against nothing but their
    /// frame rendering).
    #[arg(long)]
    pub no_truth: bool,
}

/// `--speed`: a positive, finite number of metres a second.
fn parse_speed(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!(
            "'{s}' is not a speed: give metres a second, a number above 0 (15 drives, 1.4 walks)"
        )),
    }
}

/// A GPU fault the window and `shot` can simulate, to test that they survive it.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaultDrill {
    /// The device is destroyed, as a driver reset loses it.
    DeviceLost,
    /// The window is minimised (its size 0 x 0) for a few frames, then restored.
    Minimised,
}

/// `shadowlab [SCENE]`: open the window.
#[derive(Args, Debug)]
pub struct OpenArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Start with "compare all methods" on: every method's counts, error and GPU times.
    #[arg(long)]
    pub compare: bool,
    /// Smoke test: close the window after this many frames.
    #[arg(long, value_name = "N")]
    pub exit_after_frames: Option<u64>,
    /// Smoke test: before closing, take a screenshot of the whole window (as F12 with
    /// "include panel" does) into this folder: a PNG and its stats JSON.
    #[arg(long, value_name = "DIR", requires = "exit_after_frames")]
    pub screenshot_dir: Option<PathBuf>,
    /// Smoke test: after the first frame, open SCENE as "Open glTF…" does; the window closes
    /// once it has loaded or failed (and then still shows the scene it had).
    #[arg(long, value_name = "SCENE", requires = "exit_after_frames")]
    pub then_open: Option<String>,
    /// Start from the defaults instead of the remembered scene, camera and settings (which
    /// are still saved when the window closes).
    #[arg(long)]
    pub fresh: bool,
    /// Fly the scene's camera path from the first frame, as the Scene tab's "Play path" does.
    #[arg(long)]
    pub play_path: bool,
    /// A CSV line per presented frame: its CPU times, how often it waited for the GPU (never,
    /// but for a screenshot or "Compare all"), and how late its GPU times are.
    #[arg(long, value_name = "FILE.csv")]
    pub frame_log: Option<PathBuf>,
    /// A test's aid, hidden: a GPU fault after the first frames, and whether the view after
    /// the recovery is the view before.
    #[arg(long, hide = true, requires = "exit_after_frames")]
    pub fault_drill: Option<FaultDrill>,
}
