//! glTF as `gltfpack` writes it (meshopt-compressed, quantized; see `shadowlab_tests::packed`)
//! loads as the scene it was packed from and shadows the same.

use render_core::frame::{FrameSettings, Method};
use render_core::scene::{ChunkSettings, ImportError, Scene, import_gltf_slice, load_builtin};
use shadowlab_tests::{city_small_street_camera, glb_bytes, packed_glb, packed_gltf, render};

fn no_chunking() -> ChunkSettings {
    ChunkSettings {
        max_extent_fraction: 0.0,
    }
}

fn city() -> Scene {
    load_builtin("city-small", 0).expect("city-small")
}

#[test]
fn a_packed_city_loads_as_the_city() {
    let city = city();
    let packed = import_gltf_slice(&packed_glb(&city), "packed.glb", &no_chunking())
        .expect("the packed city loads");
    assert_eq!(packed.instances.len(), city.instances.len());
    assert_eq!(packed.triangle_count(), city.triangle_count());
    for (p, c) in packed.instances.iter().zip(&city.instances) {
        assert_eq!(p.name, c.name);
        // 16-bit steps over each mesh's box: within a part in 65535 of its size.
        let size = (c.aabb_in_world.max - c.aabb_in_world.min).max_element();
        let tolerance = size / 65535.0 + 1e-4;
        assert!(
            p.aabb_in_world
                .min
                .abs_diff_eq(c.aabb_in_world.min, tolerance)
                && p.aabb_in_world
                    .max
                    .abs_diff_eq(c.aabb_in_world.max, tolerance),
            "{}: {:?} against {:?}",
            c.name,
            p.aabb_in_world,
            c.aabb_in_world
        );
    }
}

#[test]
fn a_packed_city_shadows_as_the_city() {
    let city = city();
    let mut packed = import_gltf_slice(&packed_glb(&city), "packed.glb", &no_chunking())
        .expect("the packed city loads");
    packed.sun = city.sun;
    let camera = city_small_street_camera();
    let settings = FrameSettings {
        sun: city.sun,
        method: Method::Frag,
        measure: true,
        ..FrameSettings::default()
    };
    let (original, original_capture) = render(&city, &camera, &settings, 256, 160);
    let (unpacked, unpacked_capture) = render(&packed, &camera, &settings, 256, 160);
    for report in [&original, &unpacked] {
        let e = report.error.expect("measured");
        assert_eq!((e.missing_shadow_px, e.extra_shadow_px), (0, 0));
    }
    // The fraction of taps that see the sun, per pixel.
    let (a, b) = (&original_capture.shadow, &unpacked_capture.shadow);
    let differing = a.iter().zip(b).filter(|(x, y)| x != y).count();
    assert!(
        differing * 200 < a.len(),
        "{differing} of {} pixels differ in shadow",
        a.len()
    );
    assert_eq!(
        original.counts.objects_visible, unpacked.counts.objects_visible,
        "the same objects are visible"
    );
}

#[test]
fn a_compressed_view_that_does_not_add_up_names_the_view() {
    let (mut document, bin) = packed_gltf(&city());
    let ext = &mut document["bufferViews"][0]["extensions"]["EXT_meshopt_compression"];
    ext["count"] = serde_json::json!(ext["count"].as_u64().expect("count") + 1);
    let error = import_gltf_slice(&glb_bytes(&document, &bin), "broken.glb", &no_chunking())
        .expect_err("a view whose elements do not fill it");
    assert!(matches!(error, ImportError::Compressed { .. }), "{error:?}");
    let message = error.to_string();
    assert!(
        message.contains("broken.glb") && message.contains("buffer view 0 (meshopt)"),
        "{message}"
    );
}
