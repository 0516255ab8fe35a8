//! Known-answer shadow tests: a box on a plane, lit from straight above and from 2 degrees.

use glam::Vec3;
use render_core::frame::{FrameSettings, PcfKernel};
use render_core::geom::Camera;
use render_core::scene::Sun;
use shadowlab_tests::{box_on_plane, expected_shadow, pixels_of, render};

const GROUND: u32 = 1; // instance 0 + 1
const BOX_HALF: f32 = 1.0;

#[test]
fn sun_at_zenith_shadows_exactly_the_ground_under_the_box() {
    let sun = Sun::from_direction(Vec3::Y);
    // The box floats 1.5 m up, so a camera from the side sees the ground under it.
    let scene = box_on_plane(20.0, Vec3::splat(2.0 * BOX_HALF), 1.5, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 4.0, 12.0),
        Vec3::ZERO,
        50f32.to_radians(),
        0.1,
        100.0,
    );
    let settings = FrameSettings {
        sun,
        ..FrameSettings::default()
    };
    let (report, capture) = render(&scene, &camera, &settings, 320, 256);
    assert_eq!(report.counts.casters_total, 2);
    assert_eq!(report.counts.receivers_visible, Some(2));

    // The PCF border: kernel half-width plus one texel, in metres.
    let texel = report.light.texel_size_m[0].max(report.light.texel_size_m[1]);
    let border = texel * (settings.shadow.pcf.width() as f32 * 0.5 + 1.0);
    let (mut inside, mut outside, mut wrong) = (0, 0, Vec::new());
    for (i, p) in pixels_of(&capture, &camera, GROUND) {
        let distance_outside = (p.x.abs() - BOX_HALF).max(p.z.abs() - BOX_HALF);
        let lit = capture.shadow[i] == 255;
        let dark = capture.shadow[i] == 0;
        if distance_outside < -border {
            inside += 1;
            if !dark {
                wrong.push((i, p, capture.shadow[i]));
            }
        } else if distance_outside > border {
            outside += 1;
            if !lit {
                wrong.push((i, p, capture.shadow[i]));
            }
        }
    }
    assert!(
        inside > 50,
        "too few ground pixels under the box are visible: {inside}"
    );
    assert!(outside > 10_000, "too few lit ground pixels: {outside}");
    assert!(
        wrong.is_empty(),
        "{} ground pixels have the wrong shadow, first: {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(5)]
    );
}

#[test]
fn grazing_sun_casts_a_long_shadow_without_acne() {
    let sun = Sun::from_azimuth_elevation_deg(0.0, 2.0);
    let scene = box_on_plane(120.0, Vec3::splat(2.0 * BOX_HALF), 0.0, sun);
    // Looking along the shadow, which falls towards -X.
    let camera = Camera::look_at(
        Vec3::new(12.0, 10.0, 0.0),
        Vec3::new(-30.0, 0.0, 0.0),
        60f32.to_radians(),
        0.1,
        300.0,
    );
    for pcf in [PcfKernel::Off, PcfKernel::K3x3] {
        let mut settings = FrameSettings {
            sun,
            ..FrameSettings::default()
        };
        settings.shadow.pcf = pcf;
        let (report, capture) = render(&scene, &camera, &settings, 384, 256);
        let texel = report.light.texel_size_m[0].max(report.light.texel_size_m[1]);
        let box_min = Vec3::new(-BOX_HALF, 0.0, -BOX_HALF);
        let box_max = Vec3::new(BOX_HALF, 2.0 * BOX_HALF, BOX_HALF);
        let (mut lit_expected, mut acne, mut far_shadow) = (0u32, 0u32, 0u32);
        let (mut shadow_expected, mut lost) = (0u32, 0u32);
        for (i, p) in pixels_of(&capture, &camera, GROUND) {
            // Skip the penumbra band: rays that pass within the PCF border of the box's edges.
            let border = texel * (pcf.width() as f32 + 1.0);
            let Some(expected_shadow) =
                expected_shadow(p, sun.direction_to_sun, box_min, box_max, border)
            else {
                continue;
            };
            if expected_shadow {
                shadow_expected += 1;
                if capture.shadow[i] == 255 {
                    lost += 1;
                }
                if capture.shadow[i] == 0 && p.x < -20.0 {
                    far_shadow += 1;
                }
            } else {
                lit_expected += 1;
                if capture.shadow[i] < 255 {
                    acne += 1;
                }
            }
        }
        assert!(
            lit_expected > 20_000,
            "{pcf}: too few lit ground pixels: {lit_expected}"
        );
        let acne_fraction = f64::from(acne) / f64::from(lit_expected);
        assert!(
            acne_fraction < 0.001,
            "{pcf}: {acne} of {lit_expected} lit pixels are shadowed ({:.3}%)",
            acne_fraction * 100.0
        );
        // Bias must not detach the shadow from its caster (peter-panning) either.
        let lost_fraction = f64::from(lost) / f64::from(shadow_expected.max(1));
        assert!(
            lost_fraction < 0.001,
            "{pcf}: {lost} of {shadow_expected} shadowed pixels are lit ({:.3}%)",
            lost_fraction * 100.0
        );
        assert!(
            far_shadow > 100,
            "{pcf}: the long shadow beyond 20 m is missing ({far_shadow} px)"
        );
    }
}
