//! Continuous clamping as Lloyd et al. do it, at object precision (`--volume-clamp boxes`,
//! `volumes/box_clamp.rs`): each caster's volume spans the depths of the boxes of the
//! receivers in the camera's view that its box overlaps across the light, found by
//! sweep-and-prune on the CPU.

use glam::Vec3;
use render_core::frame::{FrameSettings, Method, ShadowSetup};
use render_core::geom::Camera;
use render_core::scene::{Mesh, PointShadow, Scene, Sun};
use render_core::truth::TruthCache;
use render_core::volumes::VolumeClamp;
use shadowlab_tests::{box_mesh, gpu, scene_of};

const SIZE: (u32, u32) = (256, 192);

/// The sun straight down on a 2 m slab from 9 to 10 m up, half over a platform (5 to 5.5 m)
/// and over a 20 m ground (-0.5 to 0 m); and a second slab far off, over a block the camera
/// cannot see. Instances: ground, platform, slab, far slab, far block.
fn slab_over_a_platform() -> (Scene, Camera) {
    let parts: Vec<(Mesh, Vec3)> = vec![
        (
            box_mesh("ground", Vec3::new(10.0, 0.25, 10.0)),
            Vec3::new(0.0, -0.25, 0.0),
        ),
        (
            box_mesh("platform", Vec3::new(1.5, 0.25, 2.0)),
            Vec3::new(-1.5, 5.25, 0.0),
        ),
        (
            box_mesh("slab", Vec3::new(1.0, 0.5, 1.0)),
            Vec3::new(0.0, 9.5, 0.0),
        ),
        (
            box_mesh("far slab", Vec3::new(1.0, 0.5, 1.0)),
            Vec3::new(30.0, 9.5, 0.0),
        ),
        (
            box_mesh("far block", Vec3::splat(1.0)),
            Vec3::new(30.0, 2.0, 0.0),
        ),
    ];
    let scene = scene_of(
        "test:slab-over-a-platform",
        Sun::from_azimuth_elevation_deg(0.0, 90.0),
        parts,
    );
    let camera = Camera::look_at(
        Vec3::new(12.0, 8.0, 12.0),
        Vec3::new(0.0, 4.0, 0.0),
        50f32.to_radians(),
        0.1,
        200.0,
    );
    (scene, camera)
}

fn settings(scene: &Scene, clamp: VolumeClamp) -> FrameSettings {
    let mut settings = FrameSettings {
        sun: scene.sun,
        setup: ShadowSetup::Volumes,
        method: Method::Bvol,
        ..FrameSettings::default()
    };
    settings.volumes.clamp = clamp;
    // Split at every gap: the intervals are the boxes' own.
    settings.volumes.vertex_pixels = Some(0);
    settings
}

#[test]
#[allow(clippy::float_cmp, reason = "hard shadows are exactly 0 or 1")]
fn clamping_by_boxes_spans_the_receivers_boxes_under_each_caster_and_changes_no_pixel() {
    let (scene, camera) = slab_over_a_platform();
    let mut truth = TruthCache::default();
    let exact = truth.exact(&scene, &camera, SIZE, scene.sun.direction_to_sun);
    let run = |clamp| {
        let (_, _, renderer, report) =
            shadowlab_tests::against_truth(&scene, &camera, &settings(&scene, clamp), SIZE);
        let light = renderer.light_at(gpu(), &exact.points).expect("read back");
        let intervals: Vec<_> = (0..scene.instances.len() as u32)
            .map(|i| renderer.read_volume_intervals(gpu(), i).expect("read back"))
            .collect();
        (light, intervals, report)
    };
    let (standard, ..) = run(VolumeClamp::None);
    let (light, intervals, report) = run(VolumeClamp::Boxes);
    // Depths from the slab's top: its own box (0 to 1 m), the platform's (4.5 to 5) and the
    // ground's (10 to 10.5), each within its padding; drawn as extrusions from each interval's
    // start past the slab's far side (1 m deep) to its end past its near side.
    let slab = intervals[2].clone().expect("the slab casts");
    let expected = [[0.0, 1.0], [3.5, 5.0], [9.0, 10.5]];
    assert_eq!(slab.len(), expected.len(), "{slab:?}");
    for (got, want) in slab.iter().zip(expected) {
        assert!(
            (got[0] - want[0]).abs() < 0.02 && (got[1] - want[1]).abs() < 0.02,
            "{slab:?}"
        );
    }
    // The far slab overlaps only the far block, which the camera cannot see: culled.
    assert_eq!(intervals[3], Some(Vec::new()), "{intervals:?}");
    // The light at every exact point is standard volumes'.
    let shadowed = light.iter().filter(|&&l| l == 0.0).count();
    assert!(shadowed > 500, "{shadowed} points in shadow");
    let differing = light.iter().zip(&standard).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0);
    let note = report
        .notes
        .iter()
        .find(|n| n.starts_with("clamping by boxes on the CPU"))
        .unwrap_or_else(|| panic!("{:?}", report.notes));
    // Ground, platform and slab in view; far slab and block not.
    assert!(note.contains(" 3 potential receivers"), "{note}");
    // Its CPU time is the frame's culling on the CPU (bench's "CPU cull ms").
    assert!(report.cpu.culling_ms > 0.0, "{:?}", report.cpu);
}

#[test]
fn clamping_by_boxes_under_a_point_light_says_it_clamps_by_points() {
    let (scene, camera) = slab_over_a_platform();
    let mut settings = settings(&scene, VolumeClamp::Boxes);
    settings.point_light = Some(PointShadow::omni(Vec3::new(0.0, 15.0, 0.0), 2.0e6));
    let (_, _, _, report) = shadowlab_tests::against_truth(&scene, &camera, &settings, SIZE);
    assert!(
        report
            .notes
            .iter()
            .any(|n| n.starts_with("clamping by boxes is the sun's")),
        "{:?}",
        report.notes
    );
}
