//! `bench --sweep maps`: many lights as Rákos measures them (GPU Pro 4, ch. 19, Figure 19.3):
//! each path (a pass per map, multiview groups, an instanced atlas) for each number of lights
//! and map size along the camera path, with the GPU time of the maps, the passes and draws
//! recorded and the CPU time of recording them. Ratios are against `traditional` in the same
//! run, its configurations interleaved frame by frame.

use std::fmt::Write as _;

use anyhow::Context as _;
use render_core::frame::{FrameReport, FrameSettings, ShadowSetup};
use render_core::geom::Camera;
use render_core::scene::CameraPath;
use render_core::shadow_view::{GeometryLoad, LayerCulling, LayeredPath, LayeredSettings};

use super::median;
use crate::cli::BenchArgs;
use crate::headless::Session;

/// Medians of one (path, lights, size) over the path's frames.
struct MapsRow {
    path: LayeredPath,
    /// The path that ran, after the adapter's fallbacks.
    ran_as: LayeredPath,
    lights: u32,
    maps: u32,
    size: u32,
    culling: LayerCulling,
    load: GeometryLoad,
    frames: usize,
    gpu_frame_ms: Option<f64>,
    /// GPU time of the maps' passes and of culling them.
    maps_ms: Option<f64>,
    passes: u32,
    draws: u32,
    triangles: u64,
    cpu_submit_ms: Option<f64>,
    cpu_culling_ms: Option<f64>,
    /// Per-layer culling's triangles tested and kept (medians over frames).
    tested: Option<f64>,
    kept: Option<f64>,
    /// Triangles the maps' clippers passed on to be rasterised (pipeline statistics).
    rasterised: Option<f64>,
    /// `traditional`'s maps time without culling over this row's, for the same lights and
    /// size.
    saved: Option<f64>,
}

/// Runs the sweep and prints (and writes) its table.
pub(super) fn sweep_maps(
    args: &BenchArgs,
    session: &mut Session,
    (base, path, template): (FrameSettings, &CameraPath, &Camera),
) -> anyhow::Result<()> {
    let sizes = if args.map_sizes.is_empty() {
        vec![base.shadow.resolution]
    } else {
        args.map_sizes.clone()
    };
    let range = LayeredSettings::MIN_RESOLUTION..=LayeredSettings::MAX_RESOLUTION;
    if let Some(size) = sizes.iter().find(|s| !range.contains(s)) {
        anyhow::bail!(
            "--map-sizes: {size} is outside {} to {}",
            range.start(),
            range.end()
        );
    }
    let available = session.scene.lights.len() as u32;
    if available == 0 {
        anyhow::bail!(
            "--sweep maps: {} has no point or spot lights (builtin:hall has 32)",
            session.scene.name
        );
    }
    let mut counts: Vec<u32> = args
        .light_counts
        .iter()
        .map(|&n| n.clamp(1, available))
        .collect();
    counts.dedup();
    let cullings = args
        .layer_cullings
        .iter()
        .map(|c| c.parse::<LayerCulling>().map_err(anyhow::Error::msg))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let paths = args
        .layered_paths
        .iter()
        .map(|p| p.parse::<LayeredPath>().map_err(anyhow::Error::msg))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let mut rows = Vec::new();
    for &size in &sizes {
        for &lights in &counts {
            let first = rows.len();
            let configs: Vec<FrameSettings> = cullings
                .iter()
                .flat_map(|&culling| paths.iter().map(move |&p| (culling, p)))
                .map(|(culling, path_kind)| {
                    let mut settings = FrameSettings {
                        setup: ShadowSetup::Lights,
                        ..base
                    };
                    settings.shadow.resolution = size;
                    settings.layered = LayeredSettings {
                        path: path_kind,
                        lights,
                        culling,
                        ..base.layered
                    };
                    settings
                })
                .collect();
            let measured = run_interleaved(session, path, template, &configs, args)?;
            for (settings, frames) in configs.iter().zip(&measured) {
                let layered = settings.layered;
                let mut row = summarise(layered.path, (lights, size, layered.culling), frames);
                row.load = base.layered.load;
                rows.push(row);
            }
            // The baseline: a pass per map, no culling (the first row when it was run).
            let traditional = rows[first..]
                .iter()
                .find(|r| r.path == LayeredPath::Traditional && r.culling == LayerCulling::None)
                .unwrap_or(&rows[first])
                .maps_ms;
            for row in &mut rows[first..] {
                row.saved = traditional.zip(row.maps_ms).map(|(t, m)| t / m.max(1e-9));
            }
        }
    }
    print!("{}", format_table(&rows));
    if let Some(csv) = &args.csv {
        std::fs::write(csv, format_csv(&rows))
            .with_context(|| format!("writing {}", csv.display()))?;
        eprintln!("wrote {}", csv.display());
    }
    if let Some(out) = &args.plot {
        let title = plot_title(&session.scene.name, &base, rows.first().map(|r| r.frames));
        super::maps_plot::plot(&plot_points(&rows), &title, out)?;
        eprintln!("wrote {}", out.display());
    }
    Ok(())
}

/// The figure's title: the scene and what makes it one of Rákos's figures.
fn plot_title(scene: &str, base: &FrameSettings, frames: Option<usize>) -> String {
    let mut title = format!("{scene}: many lights' maps");
    let load = load_name(base.layered.load);
    if load != "-" {
        let _ = write!(title, ", {load}");
    }
    if base.layered.sun {
        title += ", with the sun's cascades";
    }
    if let Some(frames) = frames {
        let _ = write!(title, " (medians of {frames} frames)");
    }
    title
}

fn plot_points(rows: &[MapsRow]) -> Vec<super::maps_plot::PlotPoint> {
    rows.iter()
        .map(|r| super::maps_plot::PlotPoint {
            colour: LayeredPath::ALL
                .iter()
                .position(|&p| p == r.path)
                .unwrap_or(0),
            style: LayerCulling::ALL
                .iter()
                .position(|&c| c == r.culling)
                .unwrap_or(0),
            series: if r.ran_as == r.path {
                format!("{}, culled {}", r.path.name(), r.culling.name())
            } else {
                format!(
                    "{} (as {}), culled {}",
                    r.path.name(),
                    r.ran_as.name(),
                    r.culling.name()
                )
            },
            size: r.size,
            maps: r.maps,
            gpu_ms: r.maps_ms,
            cpu_ms: r.cpu_submit_ms,
        })
        .collect()
}

/// What a frame's GPU counted, read after it (so not in its times): the triangles culling
/// kept, and those the maps' clippers passed on to be rasterised (pipeline statistics).
struct FrameCounts {
    kept: Option<u64>,
    rasterised: Option<u64>,
}

/// Warm-up frames, then the measured ones along the path, each with its counts: every
/// configuration renders each frame in turn, each with its own renderer, so that a change
/// of the machine's pace during the run (a software adapter's threads share the CPU with
/// everything else) falls on all of them alike.
fn run_interleaved(
    session: &mut Session,
    path: &CameraPath,
    template: &Camera,
    configs: &[FrameSettings],
    args: &BenchArgs,
) -> anyhow::Result<Vec<Vec<(FrameReport, FrameCounts)>>> {
    let frames = args.frames.max(1);
    let options = super::RunOptions::from(args);
    let mut renderers: Vec<_> = configs
        .iter()
        .map(|_| render_core::frame::FrameRenderer::new(&session.ctx))
        .collect();
    let mut measured: Vec<Vec<_>> = configs.iter().map(|_| Vec::new()).collect();
    for frame in 0..args.warmup + frames {
        let camera = super::camera_at(path, template, (frame, &options));
        for ((settings, renderer), out) in configs.iter().zip(&mut renderers).zip(&mut measured) {
            std::mem::swap(&mut session.renderer, renderer);
            let result = measure_frame(session, &camera, settings);
            std::mem::swap(&mut session.renderer, renderer);
            let measured = result?;
            if frame >= args.warmup {
                out.push(measured);
            }
        }
    }
    Ok(measured)
}

/// One frame and what its GPU counted.
fn measure_frame(
    session: &mut Session,
    camera: &Camera,
    settings: &FrameSettings,
) -> anyhow::Result<(FrameReport, FrameCounts)> {
    let (_, report) = session.frame(camera, settings)?;
    let culled = report
        .layered
        .is_some_and(|f| f.culling != LayerCulling::None);
    let kept = if culled {
        let kept = session.renderer.lights_kept_triangles(&session.ctx)?;
        Some(kept.iter().map(|&k| u64::from(k)).sum())
    } else {
        None
    };
    let passes = session.renderer.lights_pass_statistics(&session.ctx)?;
    let rasterised = (!passes.is_empty()).then(|| passes.iter().map(|p| p.rasterised).sum());
    Ok((report, FrameCounts { kept, rasterised }))
}

fn summarise(
    path: LayeredPath,
    (lights, size, culling): (u32, u32, LayerCulling),
    frames: &[(FrameReport, FrameCounts)],
) -> MapsRow {
    let collect = |f: &dyn Fn(&FrameReport) -> Option<f64>| {
        median(frames.iter().map(|(r, _)| r).filter_map(f).collect())
    };
    let facts = frames.last().and_then(|(r, _)| r.layered);
    MapsRow {
        path,
        ran_as: facts.map_or(path, |f| f.path),
        lights,
        maps: facts.map_or(0, |f| f.maps),
        size,
        culling,
        load: GeometryLoad::default(),
        frames: frames.len(),
        gpu_frame_ms: collect(&FrameReport::gpu_total_ms),
        // The maps' passes and the culling's compute before them.
        maps_ms: collect(&|r| {
            r.shadow_pass_ms().map(|ms| {
                ms + r
                    .gpu_ms(render_core::frame::pass_label::CULLING)
                    .unwrap_or(0.0)
            })
        }),
        passes: facts.map_or(0, |f| f.passes),
        draws: facts.map_or(0, |f| f.draws),
        triangles: facts.map_or(0, |f| f.triangles),
        cpu_submit_ms: collect(&|r| r.layered.map(|f| f.cpu_submit_ms)),
        cpu_culling_ms: collect(&|r| Some(r.cpu.culling_ms)),
        tested: collect(&|r| {
            r.layered
                .filter(|f| f.culling != LayerCulling::None)
                .map(|f| f.triangles_tested as f64)
        }),
        kept: median(
            frames
                .iter()
                .filter_map(|(_, c)| c.kept.map(|k| k as f64))
                .collect(),
        ),
        rasterised: median(
            frames
                .iter()
                .filter_map(|(_, c)| c.rasterised.map(|r| r as f64))
                .collect(),
        ),
        saved: None,
    }
}

const COLUMNS: [&str; 17] = [
    "path",
    "culling",
    "load",
    "lights",
    "maps",
    "size",
    "frames",
    "GPU frame ms",
    "maps+cull ms",
    "traditional/this",
    "passes",
    "draws",
    "triangles tested",
    "kept",
    "rasterised",
    "CPU submit ms",
    "CPU cull ms",
];

/// The geometry load in words: `-`, `no raster`, `work 16`, `no raster, work 16`.
fn load_name(load: GeometryLoad) -> String {
    let mut parts = Vec::new();
    if load.no_raster {
        parts.push("no raster".to_owned());
    }
    if load.vertex_work > 0 {
        parts.push(format!("work {}", load.vertex_work));
    }
    if parts.is_empty() {
        "-".into()
    } else {
        parts.join(", ")
    }
}

fn cells(r: &MapsRow) -> [String; 17] {
    let opt = |v: Option<f64>| v.map_or_else(|| "n/a".into(), |v| format!("{v:.2}"));
    let path = if r.ran_as == r.path {
        r.path.name().to_owned()
    } else {
        format!("{} (as {})", r.path.name(), r.ran_as.name())
    };
    let count = |v: Option<f64>| v.map_or_else(|| "-".into(), |v| format!("{v:.0}"));
    [
        path,
        r.culling.name().to_owned(),
        load_name(r.load),
        r.lights.to_string(),
        r.maps.to_string(),
        r.size.to_string(),
        r.frames.to_string(),
        opt(r.gpu_frame_ms),
        opt(r.maps_ms),
        r.saved.map_or_else(|| "-".into(), |s| format!("{s:.2}x")),
        r.passes.to_string(),
        r.draws.to_string(),
        count(r.tested),
        count(r.kept),
        count(r.rasterised),
        r.cpu_submit_ms
            .map_or_else(|| "n/a".into(), |v| format!("{v:.3}")),
        opt(r.cpu_culling_ms),
    ]
}

fn format_table(rows: &[MapsRow]) -> String {
    let lines: Vec<Vec<String>> = std::iter::once(COLUMNS.map(str::to_owned).to_vec())
        .chain(rows.iter().map(|r| cells(r).to_vec()))
        .collect();
    super::table::aligned(&lines, 1)
}

fn format_csv(rows: &[MapsRow]) -> String {
    let mut out = String::from(
        "path,ran_as,culling,no_raster,vertex_work,lights,maps,size,frames,gpu_frame_ms,maps_ms,traditional_over_this,passes,draws,triangles,triangles_tested,triangles_kept,triangles_rasterised,cpu_submit_ms,cpu_culling_ms\n",
    );
    let opt = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v:.4}"));
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.path.name(),
            r.ran_as.name(),
            r.culling.name(),
            r.load.no_raster,
            r.load.vertex_work,
            r.lights,
            r.maps,
            r.size,
            r.frames,
            opt(r.gpu_frame_ms),
            opt(r.maps_ms),
            opt(r.saved),
            r.passes,
            r.draws,
            r.triangles,
            opt(r.tested),
            opt(r.kept),
            opt(r.rasterised),
            opt(r.cpu_submit_ms),
            opt(r.cpu_culling_ms)
        );
    }
    out
}
