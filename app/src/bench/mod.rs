//! `shadowlab bench`: fly a camera path with each method and print medians, optionally
//! sweeping shadow-map size (Bittner's Table 4), sun elevation (Bittner's Figure 7), cascade
//! counts, split schemes, the practical split's lambda, shadow volumes' clamping and slices,
//! or many lights' paths, counts and map sizes (`maps.rs`).

mod maps;
mod maps_plot;
mod objects;
mod pace;
mod slices_plot;
mod sweeps;
mod table;

pub(crate) use pace::{camera_at, pace};
pub(crate) use sweeps::{SweepValues, settings as sweep_settings};

pub(crate) use table::{COLUMNS, format_csv, row_cells};

use anyhow::Context as _;
use render_core::frame::{FrameRenderer, FrameReport, FrameSettings, Method, pass_label};
use render_core::geom::Camera;
use render_core::scene::{CameraPath, SceneFacts};

use crate::cli::{BenchArgs, Sweep, parse_methods};
use crate::headless::Session;
use table::{format_passes, format_table};

/// Medians of one method's measured frames under one setting.
#[derive(Clone, Debug, serde::Serialize)]
pub(crate) struct BenchRow {
    /// The swept setting, e.g. `res 2048` or `sun 30°`; empty without a sweep.
    pub(crate) setting: String,
    pub(crate) method: String,
    pub(crate) frames: usize,
    pub(crate) frame_ms: f64,
    pub(crate) gpu_frame_ms: Option<f64>,
    pub(crate) shadow_pass_ms: Option<f64>,
    /// The GPU methods' receiver mask, pyramids and caster tests.
    pub(crate) culling_ms: Option<f64>,
    /// CPU time of culling, and of shadow volumes' clamping where the CPU does it (exact,
    /// boxes).
    pub(crate) cpu_culling_ms: Option<f64>,
    pub(crate) casters_drawn: f64,
    pub(crate) shadow_triangles: f64,
    pub(crate) casters_total: u32,
    pub(crate) casters_oracle: f64,
    pub(crate) tightness: Option<f64>,
    /// Worst frame's missing + extra shadow pixels.
    pub(crate) error_px_max: u32,
    /// Against the exact shadow: the median over frames of missing + extra pixels, and of
    /// their share of the counted pixels in percent.
    pub(crate) exact_error: (Option<f64>, Option<f64>),
    /// The median over frames of the differing pixels off the exact picture's edges: the same
    /// statistic as `exact_error`'s total, so the part never exceeds the whole.
    pub(crate) exact_off_edge_px: Option<f64>,
    /// Worst frame's differing pixels off the exact picture's edges.
    pub(crate) exact_off_edge_px_max: Option<u32>,
    /// Worst frame's flicker (pixels whose shadow changed) after a 1 cm move and a 0.1 degree
    /// turn, with `--flicker`.
    pub(crate) flicker: Option<(u32, u32)>,
    /// Undersampling in octaves: the median over frames of each frame's median and 95th
    /// percentile.
    pub(crate) undersampling: (Option<f64>, Option<f64>),
    /// Shadow volumes' fill, millions of fragments: the median frame's and the worst.
    pub(crate) fill_m: (Option<f64>, Option<f64>),
    /// Each measured frame's fill, fragments (shadow volumes).
    pub(crate) fill_frames: Vec<u64>,
    /// The first setting's baseline fill over this row's, frame by frame: the mean and the
    /// largest ratio (Lloyd's average and peak savings).
    pub(crate) fill_saved: Option<(f64, f64)>,
    /// Each measured frame's GPU time of the shadow volumes' stencil pass, ms (Lloyd's
    /// "shadow volume rendering time": the culling's and clamping's compute is apart).
    pub(crate) volume_pass_frames: Vec<f64>,
    /// The first setting's baseline stencil-pass time over this row's, frame by frame: the
    /// mean and the largest ratio (Lloyd's average and peak speed-up).
    pub(crate) volume_pass_saved: Option<(f64, f64)>,
    /// Baseline GPU frame time / this method's, under the same setting.
    pub(crate) speed_up: Option<f64>,
    /// Median GPU ms per pass label (and depth: steps inside a pass are 1), in frame order.
    pub(crate) passes: Vec<(String, u32, f64)>,
    /// Virtual maps: the medians of pages marked, resident, drawn and refused, of the
    /// texels drawn and the texels visible pixels read, of the pages refreshed, and of the
    /// cull's page flags under casters and flags and hierarchy cells it read.
    pub(crate) pages: Option<[f64; 11]>,
    /// Virtual maps: the share of the measured frames' marked pages that the cache served
    /// (not drawn, not refused), over all of them.
    pub(crate) cache_hit_rate: Option<f64>,
}

pub fn bench(args: &BenchArgs) -> anyhow::Result<()> {
    let methods = parse_methods(&args.methods)?;
    if args.plot.is_some() && !matches!(args.sweep, Some(Sweep::Maps | Sweep::Slices)) {
        anyhow::bail!("--plot draws `--sweep maps` and `--sweep slices` only");
    }
    // Each size of the city is a scene of its own (`objects.rs`).
    if args.sweep == Some(Sweep::Objects) {
        return objects::sweep_objects(args, &methods);
    }
    let mut session = Session::open(&args.scene, &args.view)?;
    let base = args.view.settings(&session.scene)?;
    let (path, template) = path_and_lens(&session, args.path.as_deref(), &args.view)?;
    let facts = SceneFacts::from(&session.scene);
    let baseline = baseline(&args.baseline, &methods)?;
    eprintln!(
        "bench {}: {} objects ({} casters), {} triangles, {}x{}, shadow map {}, path '{}', {} frames after {} warm-up, \
         speed-up against {}, on {}",
        facts.name,
        facts.objects,
        facts.casters,
        facts.triangles,
        session.width,
        session.height,
        base.shadow.resolution,
        path.name,
        args.frames.max(1),
        args.warmup,
        baseline.name(),
        session.ctx.adapter_description()
    );
    if let (Some(speed), Some((per_frame, flown))) =
        (args.speed, pace(&path, &RunOptions::from(args))?)
    {
        eprintln!(
            "camera at {speed} m/s: {per_frame:.2} m a frame, {flown:.0} of the path's {:.0} m",
            path.length_m()
        );
    }
    if args.sweep == Some(Sweep::Maps) {
        return maps::sweep_maps(args, &mut session, (base, &path, &template));
    }

    let settings_list = match args.sweep {
        Some(sweep) => sweep_settings(sweep, &base, &SweepValues::from(args))?,
        None => vec![(String::new(), base)],
    };
    let mut rows = Vec::new();
    for (setting, settings) in settings_list {
        let first = rows.len();
        for &method in &methods {
            let reports = run_path(
                &mut session,
                (&path, &template),
                &FrameSettings { method, ..settings },
                &RunOptions::from(args),
                &mut |_| {},
            )?;
            rows.push(summarise(&setting, method.name(), &reports));
        }
        set_speed_ups(&mut rows[first..], baseline.name());
    }
    set_fill_saved(&mut rows, baseline.name());
    print_rows(&rows, baseline.name(), args)?;
    // `--plot` is checked above to come with maps (returned already) or slices.
    if let Some(out) = &args.plot {
        let title = format!(
            "{}: discrete clamping's slices (Lloyd's Figure 9), {}x{}, {} frame{}",
            facts.name,
            session.width,
            session.height,
            args.frames.max(1),
            if args.frames > 1 { "s" } else { "" }
        );
        slices_plot::plot(&rows, baseline.name(), &title, out)?;
        eprintln!("wrote {}", out.display());
    }
    Ok(())
}

/// Each row's speed-up: the baseline method's GPU frame time over the row's, among `rows` (one
/// setting's).
fn set_speed_ups(rows: &mut [BenchRow], baseline: &str) {
    let baseline_ms = rows
        .iter()
        .find(|r| r.method == baseline)
        .and_then(|r| r.gpu_frame_ms);
    for row in rows {
        row.speed_up = baseline_ms
            .zip(row.gpu_frame_ms)
            .map(|(b, m)| b / m.max(1e-9));
    }
}

/// The table, the passes with `--passes`, the CSV with `--csv`.
fn print_rows(rows: &[BenchRow], baseline: &str, args: &BenchArgs) -> anyhow::Result<()> {
    print!("{}", format_table(rows, baseline));
    if let Some(pixels) = render_core::volumes::measured_pixels_per_vertex() {
        println!(
            "\nclamped volumes' V > R rule: a vertex is worth {pixels:.1} pixels, measured at \
             start-up (`--volume-vertex-pixels` fixes it)"
        );
    }
    if args.passes {
        print!("\nGPU ms per pass (median)\n{}", format_passes(rows));
    }
    if let Some(csv) = &args.csv {
        std::fs::write(csv, format_csv(rows))
            .with_context(|| format!("writing {}", csv.display()))?;
        eprintln!("wrote {}", csv.display());
    }
    Ok(())
}

/// Per row, the fill the first setting's baseline row draws over the row's own, and the
/// same for the stencil pass's time, frame by frame (the same path, so frame k is the same
/// view): their means and their peaks.
pub(crate) fn set_fill_saved(rows: &mut [BenchRow], baseline: &str) {
    let Some(first) = rows.first().map(|r| r.setting.clone()) else {
        return;
    };
    let Some(reference) = rows
        .iter()
        .find(|r| r.setting == first && r.method == baseline)
        .cloned()
    else {
        return;
    };
    let fill = |r: &BenchRow| r.fill_frames.iter().map(|&f| f as f64).collect::<Vec<_>>();
    for row in rows.iter_mut() {
        row.fill_saved = saved(&fill(&reference), &fill(row));
        row.volume_pass_saved = saved(&reference.volume_pass_frames, &row.volume_pass_frames);
    }
}

/// The mean and the largest of `reference[k] / own[k]`, when every frame of `own` has a
/// positive figure to divide by.
fn saved(reference: &[f64], own: &[f64]) -> Option<(f64, f64)> {
    let ratios: Vec<f64> = reference
        .iter()
        .zip(own)
        .filter(|(_, own)| **own > 0.0)
        .map(|(base, own)| base / own)
        .collect();
    (!ratios.is_empty() && ratios.len() == own.len()).then(|| {
        let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
        (mean, ratios.iter().copied().fold(0.0, f64::max))
    })
}

/// `--baseline`, or when that method is not among those run, the first one.
fn baseline(name: &str, methods: &[Method]) -> anyhow::Result<Method> {
    let wanted: Option<Method> = name.parse().ok();
    wanted
        .filter(|m| methods.contains(m))
        .or_else(|| methods.first().copied())
        .context("no method to run")
}

/// The camera path a run flies (`--path`, else the scene's own) and the camera whose lens
/// and up it flies with.
pub(crate) fn path_and_lens(
    session: &Session,
    path: Option<&std::path::Path>,
    view: &crate::cli::ViewArgs,
) -> anyhow::Result<(CameraPath, Camera)> {
    let path = match path {
        Some(p) => CameraPath::load(p)?,
        None => CameraPath::default_for(&session.scene),
    };
    Ok((path, view.camera(&session.scene, session.aspect())?))
}

/// How a run flies its path: `bench`'s options, which `report` shares.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RunOptions {
    /// Measured frames along the path, after `warmup` frames at its start.
    pub frames: u32,
    pub warmup: u32,
    /// Cars drive from `time` seconds on, 1/30 s a frame (`--animate`).
    pub animate: bool,
    pub time: f64,
    /// Skip the exact shadow; measure flicker.
    pub no_truth: bool,
    pub flicker: bool,
    /// The sun turns about the up axis this many degrees a second, 1/30 s a frame.
    pub moving_sun_deg_per_s: f32,
    /// The camera flies the path from its start at this many metres a second, 1/30 s a
    /// frame; without it the measured frames spread over the whole path.
    pub speed_m_per_s: Option<f32>,
}

impl From<&BenchArgs> for RunOptions {
    fn from(args: &BenchArgs) -> Self {
        Self {
            frames: args.frames,
            warmup: args.warmup,
            animate: args.animate,
            time: args.view.time.unwrap_or(0.0),
            no_truth: args.no_truth,
            flicker: args.flicker,
            moving_sun_deg_per_s: args.moving_sun.unwrap_or(0.0),
            speed_m_per_s: args.speed,
        }
    }
}

/// The path with one method: warm-up frames, then measured ones. Each view is rendered twice,
/// timed without measurement passes and then measured for error and oracle (and, after the
/// warm-up, against the exact shadow), so measuring never shows in the times. A fresh renderer
/// per run: no method inherits another's state. `done` hears of each frame as it ends.
pub(crate) fn run_path(
    session: &mut Session,
    (path, template): (&CameraPath, &Camera),
    settings: &FrameSettings,
    options: &RunOptions,
    done: &mut dyn FnMut(u32),
) -> anyhow::Result<Vec<(f64, FrameReport)>> {
    let mut settings = *settings;
    let (azimuth, elevation) = settings.sun.azimuth_elevation_deg();
    let frames = options.frames.max(1);
    pace(path, options)?;
    session.renderer = FrameRenderer::new(&session.ctx);
    let mut reports = Vec::new();
    for frame in 0..options.warmup + frames {
        let camera = camera_at(path, template, (frame, options));
        if options.moving_sun_deg_per_s != 0.0 {
            let turned = options.moving_sun_deg_per_s * frame as f32 / 30.0;
            settings.sun =
                render_core::scene::Sun::from_azimuth_elevation_deg(azimuth + turned, elevation);
        }
        if options.animate {
            session.animate(options.time + f64::from(frame) / 30.0);
        } else {
            session.settle(&camera, &settings)?;
        }
        let (wall_ms, mut report) = session.frame(&camera, &settings)?;
        let (_, measured) = session.frame(
            &camera,
            &FrameSettings {
                measure: true,
                ..settings
            },
        )?;
        report.counts.casters_oracle = measured.counts.casters_oracle;
        // Shadow volumes count their fill when measuring (or with the fill overlay on).
        report.volume_fill = report.volume_fill.or(measured.volume_fill);
        report.error = measured.error;
        report.undersampling = measured.undersampling;
        // The virtual maps count the texels pixels read when measuring.
        if let (Some(pages), Some(m)) = (report.virtual_pages.as_mut(), measured.virtual_pages) {
            pages.texels_sampled = m.texels_sampled;
        }
        if frame >= options.warmup && !options.no_truth && settings.exact_truth_applies() {
            report.exact_error = Some(session.exact_error(&camera, &settings)?);
        }
        if frame >= options.warmup && options.flicker {
            report.flicker = Some(session.flicker(&camera, &settings)?);
        }
        if frame >= options.warmup {
            reports.push((wall_ms, report));
        }
        done(frame);
    }
    Ok(reports)
}

pub(crate) fn median(mut values: Vec<f64>) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let mid = values.len() / 2;
    Some(if values.len().is_multiple_of(2) {
        (values[mid - 1] + values[mid]) * 0.5
    } else {
        values[mid]
    })
}

pub(crate) fn summarise(setting: &str, method: &str, reports: &[(f64, FrameReport)]) -> BenchRow {
    let collect = |f: &dyn Fn(&(f64, FrameReport)) -> Option<f64>| {
        median(reports.iter().filter_map(f).collect())
    };
    BenchRow {
        setting: setting.to_owned(),
        method: method.to_owned(),
        frames: reports.len(),
        frame_ms: collect(&|(wall, _)| Some(*wall)).unwrap_or(0.0),
        gpu_frame_ms: collect(&|(_, r)| r.gpu_total_ms()),
        shadow_pass_ms: collect(&|(_, r)| r.shadow_pass_ms()),
        // The virtual maps' marking, allocation and per-page cull are their culling.
        culling_ms: collect(&|(_, r)| {
            r.gpu_ms(pass_label::CULLING)
                .or_else(|| r.gpu_ms(pass_label::VIRTUAL_PAGES))
        }),
        cpu_culling_ms: collect(&|(_, r)| Some(r.cpu.culling_ms)),
        casters_drawn: collect(&|(_, r)| Some(f64::from(r.counts.casters_rendered))).unwrap_or(0.0),
        shadow_triangles: collect(&|(_, r)| Some(r.counts.triangles_shadow as f64)).unwrap_or(0.0),
        casters_total: reports.first().map_or(0, |(_, r)| r.counts.casters_total),
        casters_oracle: collect(&|(_, r)| r.counts.casters_oracle.map(f64::from)).unwrap_or(0.0),
        tightness: collect(&|(_, r)| r.tightness()),
        error_px_max: reports
            .iter()
            .filter_map(|(_, r)| r.error.map(|e| e.missing_shadow_px + e.extra_shadow_px))
            .max()
            .unwrap_or(0),
        undersampling: (
            collect(&|(_, r)| r.undersampling.map(|u| f64::from(u.median_octaves))),
            collect(&|(_, r)| r.undersampling.map(|u| f64::from(u.p95_octaves))),
        ),
        exact_error: (
            collect(&|(_, r)| {
                r.exact_error
                    .map(|e| f64::from(e.missing_shadow_px + e.extra_shadow_px))
            }),
            collect(&|(_, r)| {
                r.exact_error.map(|e| {
                    100.0 * f64::from(e.missing_shadow_px + e.extra_shadow_px)
                        / f64::from(e.visible_px.max(1))
                })
            }),
        ),
        exact_off_edge_px: collect(&|(_, r)| {
            r.exact_error.and_then(|e| e.off_edge_px).map(f64::from)
        }),
        exact_off_edge_px_max: reports
            .iter()
            .filter_map(|(_, r)| r.exact_error.and_then(|e| e.off_edge_px))
            .max(),
        flicker: reports
            .iter()
            .filter_map(|(_, r)| r.flicker.map(|f| (f.moved_px, f.turned_px)))
            .reduce(|a, b| (a.0.max(b.0), a.1.max(b.1))),
        fill_m: (
            collect(&|(_, r)| r.volume_fill.map(|f| f.fragments as f64 / 1e6)),
            reports
                .iter()
                .filter_map(|(_, r)| r.volume_fill.map(|f| f.fragments as f64 / 1e6))
                .reduce(f64::max),
        ),
        fill_frames: reports
            .iter()
            .filter_map(|(_, r)| r.volume_fill.map(|f| f.fragments))
            .collect(),
        fill_saved: None,
        volume_pass_frames: reports
            .iter()
            .filter_map(|(_, r)| r.gpu_ms(pass_label::SHADOW_VOLUMES))
            .collect(),
        volume_pass_saved: None,
        speed_up: None,
        passes: median_passes(reports),
        pages: pages_medians(reports),
        cache_hit_rate: cache_hit_rate(reports),
    }
}

fn pages_medians(reports: &[(f64, FrameReport)]) -> Option<[f64; 11]> {
    let pages: Vec<_> = reports
        .iter()
        .filter_map(|(_, r)| r.virtual_pages)
        .collect();
    if pages.is_empty() {
        return None;
    }
    let of = |f: fn(&render_core::technique::VirtualPages) -> Option<u64>| {
        median(
            pages
                .iter()
                .filter_map(|p| f(p).map(|v| v as f64))
                .collect(),
        )
        .unwrap_or(0.0)
    };
    Some([
        of(|p| Some(p.pages_marked.into())),
        of(|p| Some(p.pages_resident.into())),
        of(|p| Some(p.pages_rendered.into())),
        of(|p| Some(p.pages_refused.into())),
        of(|p| Some(p.texels_rendered)),
        of(|p| p.texels_sampled),
        of(|p| Some(p.pages_refreshed.into())),
        of(|p| Some(p.cull_pages_spanned.into())),
        of(|p| Some(p.cull_flag_reads.into())),
        of(|p| Some(p.moved_pages_occluded.into())),
        of(|p| Some(p.caster_pages_occluded.into())),
    ])
}

fn cache_hit_rate(reports: &[(f64, FrameReport)]) -> Option<f64> {
    let (hits, marked) =
        reports
            .iter()
            .filter_map(|(_, r)| r.virtual_pages)
            .fold((0u64, 0u64), |(h, m), p| {
                (
                    h + u64::from(p.pages_served()),
                    m + u64::from(p.pages_marked),
                )
            });
    (marked > 0).then(|| hits as f64 / marked as f64)
}

fn median_passes(reports: &[(f64, FrameReport)]) -> Vec<(String, u32, f64)> {
    let per_frame: Vec<_> = reports.iter().map(|(_, r)| r.gpu_passes()).collect();
    let mut labels: Vec<(String, u32)> = Vec::new();
    for pass in per_frame.iter().flatten() {
        if !labels
            .iter()
            .any(|(l, d)| *l == pass.label && *d == pass.depth)
        {
            labels.push((pass.label.clone(), pass.depth));
        }
    }
    labels
        .into_iter()
        .filter_map(|(label, depth)| {
            let times = per_frame
                .iter()
                .flatten()
                .filter(|t| t.label == label && t.depth == depth)
                .map(|t| t.gpu_ms)
                .collect();
            median(times).map(|ms| (label, depth, ms))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_even_and_odd_counts() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(vec![4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(vec![]), None);
    }

    #[test]
    fn baseline_falls_back_to_the_first_method() {
        assert_eq!(
            baseline("vfc", &[Method::None, Method::Vfc]).unwrap(),
            Method::Vfc
        );
        assert_eq!(
            baseline("ref", &[Method::Vfc, Method::None]).unwrap(),
            Method::Vfc
        );
        assert!(baseline("ref", &[]).is_err());
    }
}
