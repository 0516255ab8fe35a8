//! The headless commands: `shot`, `bench`, `scenes`. Same frame code as the window.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Context as _;
use render_core::frame::{
    FrameCapture, FrameInput, FrameRenderer, FrameReport, FrameSettings, SceneGpu, pass_label,
};
use render_core::geom::Camera;
use render_core::gpu::GpuContext;
use render_core::scene::{BUILTIN_SCENES, CameraPath, Scene, SceneFacts};
use serde_json::json;

use crate::cli::{BenchArgs, SceneArgs, ShotArgs, ViewArgs, parse_methods};
use crate::scene_source::load_scene;

pub fn list_scenes() {
    for s in BUILTIN_SCENES {
        println!("builtin:{:<12} {}", s.name, s.description);
    }
}

/// A scene on the GPU with a renderer, for headless frames at one size.
struct Session {
    scene: Scene,
    ctx: GpuContext,
    scene_gpu: SceneGpu,
    renderer: FrameRenderer,
    width: u32,
    height: u32,
}

impl Session {
    fn open(scene_args: &SceneArgs, view: &ViewArgs) -> anyhow::Result<Self> {
        let scene = load_scene(&scene_args.scene, scene_args.seed, scene_args.chunking())?;
        let (width, height) = view.size()?;
        let ctx = GpuContext::headless()?;
        let scene_gpu = SceneGpu::new(&ctx, &scene);
        let renderer = FrameRenderer::new(&ctx);
        Ok(Self {
            scene,
            ctx,
            scene_gpu,
            renderer,
            width,
            height,
        })
    }

    fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    /// Renders one frame, waits for the GPU, and returns the report with its wall-clock time.
    fn frame(
        &mut self,
        camera: &Camera,
        settings: &FrameSettings,
    ) -> anyhow::Result<(f64, FrameReport)> {
        let input = FrameInput {
            camera,
            width: self.width,
            height: self.height,
            settings,
        };
        let started = Instant::now();
        let report =
            self.renderer
                .render_and_wait(&self.ctx, &self.scene, &self.scene_gpu, &input)?;
        Ok((started.elapsed().as_secs_f64() * 1000.0, report))
    }
}

pub fn shot(args: &ShotArgs) -> anyhow::Result<()> {
    let mut session = Session::open(&args.scene, &args.view)?;
    let camera = args.view.camera(&session.scene, session.aspect())?;
    let settings = FrameSettings {
        measure: true,
        ..args.view.settings(&session.scene)?
    };
    let (wall_ms, report) = session.frame(&camera, &settings)?;
    let (scene, ctx, width, height) = (&session.scene, &session.ctx, session.width, session.height);
    let capture = FrameCapture::read(
        ctx,
        session
            .renderer
            .targets()
            .context("no targets after a frame")?,
    )?;
    write_png(&capture.color, &args.out)?;
    let stats_path = args
        .stats
        .clone()
        .unwrap_or_else(|| args.out.with_extension("json"));
    let mut stats = stats_json(scene, &settings, &camera, &report, ctx, wall_ms);
    if args.detail {
        stats["objects_detail"] = objects_detail(&session, &report)?;
    }
    std::fs::write(&stats_path, serde_json::to_string_pretty(&stats)?)
        .with_context(|| format!("writing {}", stats_path.display()))?;
    println!(
        "{}: {}x{}, {} of {} casters drawn, {} receivers visible; stats in {}",
        args.out.display(),
        width,
        height,
        report.counts.casters_rendered,
        report.counts.casters_total,
        report
            .counts
            .receivers_visible
            .map_or_else(|| "?".into(), |n| n.to_string()),
        stats_path.display()
    );
    Ok(())
}

/// Writes a PNG, creating its folder; the error names the file.
pub fn write_png(image: &image::RgbaImage, path: &Path) -> anyhow::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("creating folder {}", dir.display()))?;
    }
    image
        .save(path)
        .with_context(|| format!("writing {}", path.display()))
}

/// One entry per object: glTF node name, `visible`, `shadow_map` (`rendered` or the stage that
/// culled it) and `oracle`.
fn objects_detail(session: &Session, report: &FrameReport) -> anyhow::Result<serde_json::Value> {
    let visible = session
        .renderer
        .read_visible(&session.ctx, &session.scene_gpu)?;
    let oracle = session
        .renderer
        .read_oracle(&session.ctx, &session.scene_gpu)?;
    let outcomes = session.renderer.caster_outcomes();
    let entries: Vec<serde_json::Value> = session
        .scene
        .instances
        .iter()
        .enumerate()
        .map(|(i, inst)| {
            json!({
                "name": inst.name,
                "visible": visible[i],
                "shadow_map": outcomes[i].describe(&report.stages),
                "oracle": oracle[i],
            })
        })
        .collect();
    Ok(serde_json::Value::Array(entries))
}

/// The stats JSON of DESIGN.md: scene, objects, method, counts, stages, `timings_ms`, and the view.
pub fn stats_json(
    scene: &Scene,
    settings: &FrameSettings,
    camera: &Camera,
    report: &FrameReport,
    ctx: &GpuContext,
    wall_ms: f64,
) -> serde_json::Value {
    let facts = SceneFacts::from(scene);
    let gpu: serde_json::Map<String, serde_json::Value> = report
        .gpu
        .iter()
        .map(|t| (t.label.clone(), json!(t.gpu_ms)))
        .collect();
    json!({
        "scene": facts.name,
        "objects": facts.objects,
        "triangles": facts.triangles,
        "method": settings.method.name(),
        "adapter": ctx.adapter_description(),
        "size": [report.width, report.height],
        "view": {
            "eye": camera.eye.to_array(),
            "forward": camera.forward.to_array(),
            "fov_deg": camera.fov_y_rad.to_degrees(),
            "near": camera.near_m,
            "far": camera.far_m,
            "sun": settings.sun.direction_to_sun.to_array(),
        },
        "shadow": settings.shadow,
        "counts": {
            "casters_total": report.counts.casters_total,
            "casters_rendered": report.counts.casters_rendered,
            "casters_oracle": report.counts.casters_oracle,
            "receivers_visible": report.counts.receivers_visible,
            "objects_visible": report.counts.objects_visible,
            "objects_drawn_camera": report.counts.objects_drawn_camera,
            "triangles_shadow": report.counts.triangles_shadow,
            "triangles_camera": report.counts.triangles_camera,
        },
        "tightness": report.tightness(),
        "error": report.error,
        "stages": report.stages,
        "timings_ms": {
            "frame_wall": wall_ms,
            "cpu_culling": report.cpu.culling_ms,
            "cpu_encode_submit": report.cpu.encode_submit_ms,
            "gpu": gpu,
            "gpu_total": report.gpu_total_ms(),
        },
        "light": report.light,
    })
}

/// Medians of one method's measured frames.
#[derive(Clone, Debug, serde::Serialize)]
struct BenchRow {
    method: String,
    frames: usize,
    frame_ms: f64,
    gpu_frame_ms: Option<f64>,
    shadow_pass_ms: Option<f64>,
    casters_drawn: f64,
    shadow_triangles: f64,
    casters_total: u32,
    casters_oracle: f64,
    tightness: Option<f64>,
    /// Worst frame's missing + extra shadow pixels.
    error_px_max: u32,
}

pub fn bench(args: &BenchArgs) -> anyhow::Result<()> {
    let methods = parse_methods(&args.methods)?;
    let mut session = Session::open(&args.scene, &args.view)?;
    let base_settings = args.view.settings(&session.scene)?;
    let path = match &args.path {
        Some(p) => CameraPath::load(p)?,
        None => CameraPath::default_for(&session.scene),
    };
    let template = args.view.camera(&session.scene, session.aspect())?;
    let frames = args.frames.max(1);
    let facts = SceneFacts::from(&session.scene);
    eprintln!(
        "bench {}: {} objects, {} triangles, {}x{}, shadow map {}, path '{}', {} frames after {} warm-up, on {}",
        facts.name,
        facts.objects,
        facts.triangles,
        session.width,
        session.height,
        base_settings.shadow.resolution,
        path.name,
        frames,
        args.warmup,
        session.ctx.adapter_description()
    );
    let mut rows = Vec::new();
    for method in methods {
        let settings = FrameSettings {
            method,
            ..base_settings
        };
        // A fresh renderer per method, so no method inherits another's state.
        session.renderer = FrameRenderer::new(&session.ctx);
        let mut reports = Vec::new();
        for frame in 0..args.warmup + frames {
            let u = frame.saturating_sub(args.warmup) as f32 / (frames.max(2) - 1) as f32;
            let key = path.sample(u);
            let camera = Camera::look_at(
                key.eye,
                key.target,
                template.fov_y_rad,
                template.near_m,
                template.far_m,
            );
            // Timed without measurement passes, then the same view again measured for error
            // and oracle, so the measurement never shows in the times.
            let (wall_ms, mut report) = session.frame(&camera, &settings)?;
            let (_, measured) = session.frame(
                &camera,
                &FrameSettings {
                    measure: true,
                    ..settings
                },
            )?;
            report.counts.casters_oracle = measured.counts.casters_oracle;
            report.error = measured.error;
            if frame >= args.warmup {
                reports.push((wall_ms, report));
            }
        }
        rows.push(summarise(method.name(), &reports));
    }
    let table = format_table(&rows);
    print!("{table}");
    if let Some(csv) = &args.csv {
        std::fs::write(csv, format_csv(&rows))
            .with_context(|| format!("writing {}", csv.display()))?;
        eprintln!("wrote {}", csv.display());
    }
    Ok(())
}

fn median(mut values: Vec<f64>) -> Option<f64> {
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

fn summarise(method: &str, reports: &[(f64, FrameReport)]) -> BenchRow {
    let collect = |f: &dyn Fn(&(f64, FrameReport)) -> Option<f64>| {
        median(reports.iter().filter_map(f).collect())
    };
    BenchRow {
        method: method.to_owned(),
        frames: reports.len(),
        frame_ms: collect(&|(wall, _)| Some(*wall)).unwrap_or(0.0),
        gpu_frame_ms: collect(&|(_, r)| r.gpu_total_ms()),
        shadow_pass_ms: collect(&|(_, r)| r.gpu_ms(pass_label::SHADOW_MAP)),
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
    }
}

const COLUMNS: [&str; 10] = [
    "method",
    "frames",
    "frame ms",
    "GPU frame ms",
    "shadow pass ms",
    "casters drawn",
    "oracle",
    "tightness",
    "shadow triangles",
    "error px (max)",
];

fn row_cells(r: &BenchRow) -> [String; 10] {
    let opt =
        |v: Option<f64>, digits: usize| v.map_or_else(|| "n/a".into(), |v| format!("{v:.digits$}"));
    [
        r.method.clone(),
        r.frames.to_string(),
        format!("{:.2}", r.frame_ms),
        opt(r.gpu_frame_ms, 2),
        opt(r.shadow_pass_ms, 2),
        format!("{:.0}", r.casters_drawn),
        format!("{:.0}", r.casters_oracle),
        opt(r.tightness, 2),
        format!("{:.0}", r.shadow_triangles),
        r.error_px_max.to_string(),
    ]
}

fn format_table(rows: &[BenchRow]) -> String {
    let cells: Vec<[String; 10]> = rows.iter().map(row_cells).collect();
    let widths: Vec<usize> = (0..COLUMNS.len())
        .map(|c| {
            cells
                .iter()
                .map(|r| r[c].len())
                .chain([COLUMNS[c].len()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut out = String::new();
    for line in std::iter::once(COLUMNS.map(str::to_owned)).chain(cells) {
        let padded: Vec<String> = line
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(c, (cell, w))| {
                if c == 0 {
                    format!("{cell:<w$}")
                } else {
                    format!("{cell:>w$}")
                }
            })
            .collect();
        let _ = writeln!(out, "{}", padded.join("  "));
    }
    out
}

fn format_csv(rows: &[BenchRow]) -> String {
    let mut out = String::from(
        "method,frames,frame_ms,gpu_frame_ms,shadow_pass_ms,casters_drawn,casters_oracle,tightness,shadow_triangles,error_px_max,casters_total\n",
    );
    let opt = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v:.4}"));
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{:.4},{},{},{},{},{},{},{},{}",
            r.method,
            r.frames,
            r.frame_ms,
            opt(r.gpu_frame_ms),
            opt(r.shadow_pass_ms),
            r.casters_drawn,
            r.casters_oracle,
            opt(r.tightness),
            r.shadow_triangles,
            r.error_px_max,
            r.casters_total
        );
    }
    out
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
}
