//! `shadowlab check [SCENE]`: the tests' hard cases on the user's own scene. Each case (the
//! scene's own view, a grazing sun, the sun at the zenith, the camera inside the largest
//! caster, looking into the sun, a view of nothing, the scene 100 km from the origin) runs
//! each technique, and passes or fails by the figures: culling error against the reference
//! maps (zero for every conservative method), numbers that are not finite, a frame that
//! cannot render, and for shadow volumes, error off the exact shadow's edges.

use glam::Vec3;
use render_core::frame::{FrameReport, FrameSettings, Method, ShadowSetup};
use render_core::geom::Camera;
use render_core::scene::{Scene, Sun};
use render_core::shadow_view::{LayeredPath, VolumeClamp};

use crate::cli::CheckArgs;
use crate::headless::Session;

/// A camera and a sun to check, and how far the scene is moved for it first (the cases with
/// a move come last: the scene stays moved).
struct Case {
    name: &'static str,
    camera: Camera,
    sun: Sun,
    scene_moved_by: Option<Vec3>,
}

/// One technique's settings.
struct Technique {
    name: &'static str,
    settings: FrameSettings,
}

/// What one (case, technique) gave.
#[derive(Debug, PartialEq)]
pub struct Outcome {
    pub culling_error_px: u32,
    pub visible_px: u32,
    /// Against the exact shadow: differing pixels, and those off its edges.
    pub exact: Option<(u32, Option<u32>)>,
    /// A number of the report that is not finite, by name.
    pub not_finite: Option<String>,
}

/// Shadow volumes may differ from the exact shadow off its edges on this share of the visible
/// pixels (the volumes issue's bound).
const VOLUME_OFF_EDGE_SHARE: f64 = 1e-4;

/// Why an outcome fails, or `None` when it passes.
pub fn verdict(technique_is_volumes: bool, outcome: &Outcome) -> Option<String> {
    if let Some(name) = &outcome.not_finite {
        return Some(format!("{name} is not a finite number"));
    }
    if outcome.culling_error_px > 0 {
        return Some(format!(
            "{} pixels differ from the reference maps of every caster (culling error)",
            outcome.culling_error_px
        ));
    }
    if technique_is_volumes
        && let Some((_, Some(off_edge))) = outcome.exact
        && f64::from(off_edge) > VOLUME_OFF_EDGE_SHARE * f64::from(outcome.visible_px.max(1))
    {
        return Some(format!(
            "{off_edge} pixels differ from the exact shadow off its edges (at most {:.2}% of \
             {} visible)",
            VOLUME_OFF_EDGE_SHARE * 100.0,
            outcome.visible_px
        ));
    }
    None
}

pub fn check(args: &CheckArgs) -> anyhow::Result<()> {
    let mut session = Session::open(&args.scene, &args.view)?;
    let base = args.view.settings(&session.scene)?;
    let view = args.view.camera(&session.scene, session.aspect())?;
    let techniques = techniques(&base, !session.scene.lights.is_empty());
    let mut failures = 0;
    let mut total = 0;
    println!(
        "check {} on {}",
        session.scene.name,
        session.ctx.adapter_description()
    );
    println!(
        "case                   technique                      result  culling error px  exact error px (off edges)"
    );
    for case in &cases(&session.scene, &view) {
        if let Some(offset) = case.scene_moved_by {
            session.move_scene(offset);
        }
        println!("{}", case_flags(case));
        for technique in &techniques {
            total += 1;
            let settings = FrameSettings {
                sun: case.sun,
                measure: true,
                ..technique.settings
            };
            let volumes = settings.setup == ShadowSetup::Volumes;
            let (result, figures) = match run(&mut session, &case.camera, &settings, args.no_truth)
            {
                Ok(outcome) => (verdict(volumes, &outcome), figures(&outcome)),
                Err(e) => (
                    Some(format!("the frame did not render: {e:#}")),
                    String::new(),
                ),
            };
            let word = if result.is_some() { "FAIL" } else { "pass" };
            println!("{:22} {:30} {word:6}  {figures}", case.name, technique.name);
            if let Some(why) = result {
                failures += 1;
                println!("    {why}");
            }
        }
    }
    if failures > 0 {
        anyhow::bail!("{failures} of {total} checks failed");
    }
    println!("all {total} checks passed");
    Ok(())
}

/// Settles and measures one view.
fn run(
    session: &mut Session,
    camera: &Camera,
    settings: &FrameSettings,
    no_truth: bool,
) -> anyhow::Result<Outcome> {
    session.settle(camera, settings)?;
    let (_, report) = session.frame(camera, settings)?;
    let exact = if !no_truth && settings.exact_truth_applies() {
        let e = session.exact_error(camera, settings)?;
        Some((e.missing_shadow_px + e.extra_shadow_px, e.off_edge_px))
    } else {
        None
    };
    let error = report.error.unwrap_or_default();
    Ok(Outcome {
        culling_error_px: error.missing_shadow_px + error.extra_shadow_px,
        visible_px: error.visible_px,
        exact,
        not_finite: not_finite(&report),
    })
}

fn figures(o: &Outcome) -> String {
    let exact = match o.exact {
        Some((px, Some(off))) => format!("{px} ({off}) of {}", o.visible_px),
        Some((px, None)) => format!("{px} of {}", o.visible_px),
        None => "-".into(),
    };
    format!("{:>16}  {exact}", o.culling_error_px)
}

/// The first number of the report's views that is not finite.
fn not_finite(report: &FrameReport) -> Option<String> {
    report.views.iter().find_map(|v| {
        let numbers = [
            ("texel size", v.texel_size_m[0]),
            ("texel size", v.texel_size_m[1]),
            ("depth range", v.depth_range_m),
        ];
        numbers
            .iter()
            .find(|(_, n)| !n.is_finite())
            .map(|(what, _)| format!("{}'s {what}", v.name))
    })
}

/// The techniques to check: culling methods on one map, LiSPSM, cascades, CC shadow volumes,
/// and the many-lights paths where the scene has lights.
fn techniques(base: &FrameSettings, lights: bool) -> Vec<Technique> {
    let base = *base;
    let with = |name, setup, method| Technique {
        name,
        settings: FrameSettings {
            setup,
            method,
            ..base
        },
    };
    let mut volumes = with(
        "volumes, conservative CC",
        ShadowSetup::Volumes,
        Method::Vfc,
    );
    volumes.settings.volumes.clamp = VolumeClamp::Conservative;
    let mut all = vec![
        with("single map, frag", ShadowSetup::Single, Method::Frag),
        with(
            "single map, dr-conservative",
            ShadowSetup::Single,
            Method::DrConservative,
        ),
        with("lispsm, vfc", ShadowSetup::Lispsm, Method::Vfc),
        with("cascades, frag", ShadowSetup::Cascades, Method::Frag),
        with("volumes, standard", ShadowSetup::Volumes, Method::None),
        volumes,
        with("virtual maps", ShadowSetup::Virtual, Method::None),
    ];
    if lights {
        let mut atlas = with("lights, atlas, frag", ShadowSetup::Lights, Method::Frag);
        atlas.settings.layered.path = LayeredPath::Atlas;
        all.push(with(
            "lights, traditional, vfc",
            ShadowSetup::Lights,
            Method::Vfc,
        ));
        all.push(atlas);
    }
    all
}

/// The hard views of `scene`, from its own `view`.
fn cases(scene: &Scene, view: &Camera) -> Vec<Case> {
    let sun = scene.sun;
    let (azimuth, _) = sun.azimuth_elevation_deg();
    let bounds = scene.bounds();
    let look = |eye: Vec3, target: Vec3| {
        Camera::look_at(eye, target, view.fov_y_rad, view.near_m, view.far_m).with_up(view.world_up)
    };
    let largest = scene
        .instances
        .iter()
        .filter(|i| i.casts_shadow)
        .max_by(|a, b| volume(&a.aabb_in_world).total_cmp(&volume(&b.aabb_in_world)));
    let inside = largest.map_or(bounds.center(), |i| i.aabb_in_world.center());
    let extent = (bounds.max - bounds.min).length().max(1.0);
    let away = bounds.max + Vec3::new(0.1, 0.05, 0.1) * extent;
    let far = Vec3::new(100_000.0, 0.0, 100_000.0);
    let case = |name, camera, sun| Case {
        name,
        camera,
        sun,
        scene_moved_by: None,
    };
    vec![
        case("the scene's view", *view, sun),
        case(
            "grazing sun (1°)",
            *view,
            Sun::from_azimuth_elevation_deg(azimuth, 1.0),
        ),
        case(
            "sun at the zenith",
            *view,
            Sun::from_azimuth_elevation_deg(azimuth, 90.0),
        ),
        case(
            "inside the largest",
            look(inside, inside + view.forward * 10.0),
            sun,
        ),
        case(
            "looking into the sun",
            look(view.eye, view.eye + sun.direction_to_sun * 10.0),
            sun,
        ),
        case(
            "a view of nothing",
            look(away, away + Vec3::new(1.0, 0.2, 1.0)),
            sun,
        ),
        Case {
            name: "100 km out",
            camera: moved(view, far),
            sun,
            scene_moved_by: Some(far),
        },
    ]
}

/// The case's view as `shot` flags, so a failure can be looked at: `  (--eye ... --sun ...)`.
fn case_flags(case: &Case) -> String {
    let v = |v: Vec3| format!("{},{},{}", v.x, v.y, v.z);
    let c = &case.camera;
    format!(
        "{}: --eye {} --target {} --fov {} --near {} --far {} --sun {}{}",
        case.name,
        v(c.eye),
        v(c.eye + c.forward),
        c.fov_y_rad.to_degrees(),
        c.near_m,
        c.far_m,
        v(case.sun.direction_to_sun),
        case.scene_moved_by
            .map_or_else(String::new, |o| format!(" (the scene moved by {})", v(o))),
    )
}

fn volume(b: &render_core::geom::Aabb) -> f32 {
    let d = (b.max - b.min).max(Vec3::ZERO);
    d.x * d.y * d.z
}

fn moved(camera: &Camera, offset: Vec3) -> Camera {
    Camera::look_at(
        camera.eye + offset,
        camera.eye + camera.forward + offset,
        camera.fov_y_rad,
        camera.near_m,
        camera.far_m,
    )
    .with_up(camera.world_up)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome() -> Outcome {
        Outcome {
            culling_error_px: 0,
            visible_px: 100_000,
            exact: Some((400, Some(5))),
            not_finite: None,
        }
    }

    #[test]
    fn a_check_fails_on_culling_error_numbers_that_are_not_finite_and_volumes_off_edges() {
        assert_eq!(verdict(false, &outcome()), None);
        assert_eq!(
            verdict(true, &outcome()),
            None,
            "5 of 100,000 is within 0.01%"
        );
        let culled_wrong = Outcome {
            culling_error_px: 1,
            ..outcome()
        };
        assert!(
            verdict(false, &culled_wrong)
                .unwrap()
                .contains("culling error")
        );
        let off = Outcome {
            exact: Some((400, Some(11))),
            ..outcome()
        };
        assert_eq!(verdict(false, &off), None, "maps may differ off the edges");
        assert!(verdict(true, &off).unwrap().contains("off its edges"));
        let nan = Outcome {
            not_finite: Some("cascade 0's texel size".into()),
            ..outcome()
        };
        assert!(
            verdict(false, &nan)
                .unwrap()
                .contains("not a finite number")
        );
    }
}
