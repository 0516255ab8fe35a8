//! The headless commands `shot` and `scenes`, and the session `bench` shares. Same frame code
//! as the window.

use std::path::Path;
use std::time::Instant;

use anyhow::Context as _;
use render_core::frame::compare::settled;
use render_core::frame::{
    Flicker, FrameCapture, FrameInput, FrameRenderer, FrameReport, FrameSettings, SceneGpu,
};
use render_core::geom::Camera;
use render_core::gpu::GpuContext;
use render_core::metrics::ShadowError;
use render_core::scene::{BUILTIN_SCENES, Scene, SceneFacts};
use render_core::truth::TruthCache;
use serde_json::json;

use crate::cli::{SceneArgs, ShotArgs, ViewArgs};
use crate::scene_source::{Loaded, load_scene};

pub fn list_scenes() {
    for s in BUILTIN_SCENES {
        println!("builtin:{:<12} {}", s.name, s.description);
    }
}

/// A scene on the GPU with a renderer, for headless frames at one size.
pub(crate) struct Session {
    pub scene: Scene,
    pub ctx: GpuContext,
    pub scene_gpu: SceneGpu,
    pub renderer: FrameRenderer,
    pub width: u32,
    pub height: u32,
    /// What the user should know about the scene (a unit that looks wrong), printed on open.
    pub scene_notes: Vec<String>,
    /// The exact shadow of the views measured so far.
    pub truth: TruthCache,
}

impl Session {
    pub fn open(scene_args: &SceneArgs, view: &ViewArgs) -> anyhow::Result<Self> {
        let Loaded {
            mut scene,
            notes: scene_notes,
        } = load_scene(scene_args.spec(), &scene_args.load_options())?;
        for note in &scene_notes {
            eprintln!("note: {note}");
        }
        if let Some(time) = view.time {
            anyhow::ensure!(
                time.is_finite(),
                "--time must be a finite number of seconds"
            );
            scene.animate(time);
        }
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
            scene_notes,
            truth: TruthCache::default(),
        })
    }

    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    /// Poses the dynamic objects as they are `time_s` into their motion, on the GPU too.
    pub fn animate(&mut self, time_s: f64) {
        let moved = self.scene.animate(time_s);
        self.scene_gpu
            .update_instances(&self.ctx, &self.scene, &moved);
    }

    /// Renders one frame, waits for the GPU, and returns the report with its wall-clock time.
    pub fn frame(
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

    /// The last frame's shadow against the exact shadow of its view (cast now, or cached).
    pub fn exact_error(
        &mut self,
        camera: &Camera,
        settings: &FrameSettings,
    ) -> anyhow::Result<ShadowError> {
        let exact = self.truth.exact_and_rays(
            &self.scene,
            camera,
            (self.width, self.height),
            settings.shadow_light(),
        );
        Ok(self.renderer.exact_error(&self.ctx, exact)?)
    }

    /// Flicker of this view: it, moved 1 cm and turned 0.1 degrees, rendered (three frames)
    /// and compared at its exact surface points.
    pub fn flicker(
        &mut self,
        camera: &Camera,
        settings: &FrameSettings,
    ) -> anyhow::Result<Flicker> {
        let input = FrameInput {
            camera,
            width: self.width,
            height: self.height,
            settings,
        };
        Ok(self.renderer.flicker(
            &self.ctx,
            (&self.scene, &self.scene_gpu),
            &mut self.truth,
            &input,
        )?)
    }

    /// Moves the scene by `offset` (`check`'s case far from the origin): a new scene on the
    /// GPU, a new renderer and no truth cached.
    pub fn move_scene(&mut self, offset: glam::Vec3) {
        self.scene = self.scene.moved_by(offset);
        self.scene_gpu = SceneGpu::new(&self.ctx, &self.scene);
        self.renderer = FrameRenderer::new(&self.ctx);
        self.truth = TruthCache::default();
    }

    /// The view as the window shows it, after settling: the picture with the legend of the
    /// overlays `settings` turns on (`report`'s screenshots).
    pub fn picture(
        &mut self,
        camera: &Camera,
        settings: &FrameSettings,
    ) -> anyhow::Result<image::RgbaImage> {
        self.settle(camera, settings)?;
        self.frame(camera, settings)?;
        let targets = self
            .renderer
            .targets()
            .context("no targets after a frame")?;
        let capture = FrameCapture::read(&self.ctx, targets)?;
        crate::legend_image::with_legend(&self.ctx, &capture.color, settings)
    }

    /// Renders the view until a method that relies on last frame's visibility in the light's
    /// view has settled: until the drawn count repeats (six frames at most). Reports then
    /// describe the steady state. Other methods need no settling.
    pub fn settle(&mut self, camera: &Camera, settings: &FrameSettings) -> anyhow::Result<()> {
        if !settings.method.temporal() {
            return Ok(());
        }
        let mut last = None;
        for frames in 1.. {
            let (_, report) = self.frame(camera, settings)?;
            let drawn = report.counts.casters_rendered;
            if settled(settings.method, last, drawn, frames) {
                break;
            }
            last = Some(drawn);
        }
        Ok(())
    }
}

/// Why a frame of many lights has no exact error.
pub const NO_TRUTH_FOR_LIGHTS: &str = "the exact shadow casts rays towards the sun or one point \
     light: many lights without the sun (--sun-cascades) have no exact shadow yet, so no exact \
     error is reported";

pub fn shot(args: &ShotArgs) -> anyhow::Result<()> {
    let mut session = Session::open(&args.scene, &args.view)?;
    let camera = args.view.camera(&session.scene, session.aspect())?;
    let settings = FrameSettings {
        measure: true,
        ..args.view.settings(&session.scene)?
    };
    if args.fault_drill == Some(crate::cli::FaultDrill::DeviceLost) {
        session.ctx.device.destroy();
    }
    session.settle(&camera, &settings)?;
    let (wall_ms, mut report) = session.frame(&camera, &settings)?;
    if !args.no_truth {
        if settings.exact_truth_applies() {
            report.exact_error = Some(session.exact_error(&camera, &settings)?);
        } else {
            report.notes.push(NO_TRUTH_FOR_LIGHTS.to_owned());
        }
    }
    if let Some(from) = args.observe_from {
        let target = args
            .observe_target
            .unwrap_or(camera.eye + camera.forward * 40.0);
        let observer = Camera::look_at(
            from,
            target,
            camera.fov_y_rad,
            camera.near_m,
            camera.far_m.max(from.distance(target) * 4.0),
        )
        .with_up(camera.world_up);
        let observed = FrameSettings {
            observer: Some(observer),
            ..settings
        };
        session.frame(&camera, &observed)?;
    }
    let (scene, ctx, width, height) = (&session.scene, &session.ctx, session.width, session.height);
    let capture = FrameCapture::read(
        ctx,
        session
            .renderer
            .targets()
            .context("no targets after a frame")?,
    )?;
    let picture = if args.no_legend {
        capture.color
    } else {
        crate::legend_image::with_legend(ctx, &capture.color, &settings)?
    };
    write_png(&picture, &args.out)?;
    let stats_path = args
        .stats
        .clone()
        .unwrap_or_else(|| args.out.with_extension("json"));
    let mut stats = stats_json(scene, &settings, &camera, &report, ctx, wall_ms);
    stats["scene_notes"] = serde_json::json!(session.scene_notes);
    if args.detail {
        stats["objects_detail"] = objects_detail(&session, &report)?;
    }
    if args.flicker {
        let flicker = session.flicker(&camera, &settings)?;
        stats["flicker"] = json!(flicker);
        println!(
            "flicker: {} pixels after moving {} m (of {} seen from both), {} after turning {}° \
             (of {}); {} counted",
            flicker.moved_px,
            render_core::frame::FLICKER_MOVE_M,
            flicker.moved_seen_px,
            flicker.turned_px,
            render_core::frame::FLICKER_TURN_DEG,
            flicker.turned_seen_px,
            flicker.counted_px
        );
    }
    std::fs::write(&stats_path, serde_json::to_string_pretty(&stats)?)
        .with_context(|| format!("writing {}", stats_path.display()))?;
    let drawn = match report.views.len() {
        0 | 1 => format!(
            "{} of {} casters drawn",
            report.counts.casters_rendered, report.counts.casters_total
        ),
        views => format!(
            "{} caster draws in {views} views ({} casters)",
            report.counts.casters_rendered, report.counts.casters_total
        ),
    };
    println!(
        "{}: {}x{}, {drawn}, {} receivers visible; stats in {}",
        args.out.display(),
        width,
        height,
        report
            .counts
            .receivers_visible
            .map_or_else(|| "?".into(), |n| n.to_string()),
        stats_path.display()
    );
    if let Some(passes) = report.volume_passes {
        println!(
            "shadow volumes: {} counted z-pass, {} z-fail; {} casters gathered by workgroups, {} kept whole past the cull's budget; {} triangles drawn ({} of quads, {} of caps)",
            passes.z_pass,
            passes.z_fail,
            passes.big_casters,
            passes.whole_past_budget,
            passes.quad_triangles + passes.cap_triangles,
            passes.quad_triangles,
            passes.cap_triangles
        );
    }
    if let Some(fill) = report.volume_fill {
        println!(
            "shadow volumes: {} fragments rasterised, {} stencil writes",
            fill.fragments, fill.stencil_writes
        );
    }
    if let Some(pixels) = render_core::volumes::measured_pixels_per_vertex() {
        println!("shadow volumes: V > R rule with a vertex worth {pixels:.1} pixels (measured)");
    }
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

/// The light that casts the frame's shadows (`--light`): the sun, or a point or spot light
/// with where it is, how bright and a spot's cone.
fn shadow_light_json(settings: &FrameSettings) -> serde_json::Value {
    let Some(light) = settings.point_light else {
        return json!({ "kind": "sun", "direction": settings.sun.direction_to_sun.to_array() });
    };
    let mut out = json!({
        "kind": "point",
        "position": light.position.to_array(),
        "intensity_cd": light.intensity_cd,
    });
    if let Some(cone) = light.cone {
        out["kind"] = json!("spot");
        out["direction"] = json!(cone.direction.to_array());
        out["inner_cone_deg"] = json!(cone.inner_rad.to_degrees());
        out["outer_cone_deg"] = json!(cone.outer_rad.to_degrees());
    }
    out
}

/// The stats JSON of DESIGN.md: scene, objects, method, counts, stages (in total and per shadow
/// view), `timings_ms`, and the view.
pub fn stats_json(
    scene: &Scene,
    settings: &FrameSettings,
    camera: &Camera,
    report: &FrameReport,
    ctx: &GpuContext,
    wall_ms: f64,
) -> serde_json::Value {
    let facts = SceneFacts::from(scene);
    let passes = report.gpu_passes();
    let by_label = |top: bool| -> serde_json::Map<String, serde_json::Value> {
        passes
            .iter()
            .filter(|t| (t.depth == 0) == top)
            .map(|t| (t.label.clone(), json!(t.gpu_ms)))
            .collect()
    };
    let (gpu, gpu_steps) = (by_label(true), by_label(false));
    json!({
        "scene": facts.name,
        "objects": facts.objects,
        "triangles": facts.triangles,
        "lights": facts.lights,
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
            "shadow_light": shadow_light_json(settings),
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
        "exact_error": report.exact_error,
        "flicker": report.flicker,
        "undersampling": report.undersampling,
        "stages": report.stages,
        "technique": report.technique,
        "views": report.views,
        "notes": report.notes,
        "shadow_failure": report.shadow_failure,
        "volume_fill": report.volume_fill,
        "volume_passes": report.volume_passes,
        "layered": report.layered,
        "virtual": report.virtual_pages,
        "timings_ms": {
            "frame_wall": wall_ms,
            "cpu_culling": report.cpu.culling_ms,
            "cpu_encode_submit": report.cpu.encode_submit_ms,
            "gpu": gpu,
            "gpu_steps": gpu_steps,
            "gpu_total": report.gpu_total_ms(),
        },
        "light": report.light,
    })
}
