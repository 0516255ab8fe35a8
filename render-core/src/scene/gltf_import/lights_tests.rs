//! `KHR_lights_punctual`: the first directional light that shines down is the scene's sun.

use glam::Vec3;
use serde_json::{Value, json};

use super::tests::{no_chunking, two_boxes};
use super::*;
use crate::scene::Sun;

/// The two boxes with lights: each `(type, rotation)` on a node of its own.
fn with_lights(lights: &[(&str, [f32; 4])]) -> Scene {
    let mut document: Value = serde_json::from_slice(&two_boxes().embedded()).expect("JSON");
    document["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    let defs: Vec<Value> = lights
        .iter()
        .enumerate()
        .map(|(i, (kind, _))| json!({"type": kind, "name": format!("light{i}")}))
        .collect();
    document["extensions"] = json!({"KHR_lights_punctual": {"lights": defs}});
    for (i, (_, rotation)) in lights.iter().enumerate() {
        let nodes = document["nodes"].as_array_mut().expect("nodes");
        nodes.push(
            json!({"rotation": rotation, "extensions": {"KHR_lights_punctual": {"light": i}}}),
        );
        let index = nodes.len() - 1;
        document["scenes"][0]["nodes"]
            .as_array_mut()
            .expect("roots")
            .push(json!(index));
    }
    import_gltf_slice(document.to_string().as_bytes(), "lit.gltf", &no_chunking()).expect("loads")
}

/// A rotation about +X by `deg` degrees, as a glTF quaternion (x, y, z, w).
fn about_x(deg: f32) -> [f32; 4] {
    let half = deg.to_radians() * 0.5;
    [half.sin(), 0.0, 0.0, half.cos()]
}

#[test]
fn the_first_directional_light_shining_down_is_the_sun() {
    // -Z turned 45 degrees down about X: the light shines along (0, -1, -1) / sqrt 2.
    let scene = with_lights(&[
        ("point", about_x(0.0)),
        ("directional", about_x(-45.0)),
        ("directional", about_x(-80.0)),
    ]);
    let expected = Vec3::new(0.0, 1.0, 1.0).normalize();
    assert!(
        scene.sun.direction_to_sun.abs_diff_eq(expected, 1e-5),
        "{:?}",
        scene.sun
    );
    let (_, elevation) = scene.sun.azimuth_elevation_deg();
    assert!((elevation - 45.0).abs() < 1e-3, "{elevation}");
}

#[test]
fn a_light_shining_up_leaves_the_default_sun() {
    let scene = with_lights(&[("directional", about_x(90.0))]);
    assert_eq!(scene.sun, Sun::default());
    assert_eq!(scene.instances.len(), 2, "the scene still loads");
}

#[test]
#[allow(
    clippy::float_cmp,
    reason = "the file's numbers are read back unchanged"
)]
fn point_and_spot_lights_are_kept_where_their_nodes_put_them() {
    let mut document: Value = serde_json::from_slice(&two_boxes().embedded()).expect("JSON");
    document["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    document["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "point", "name": "lamp", "color": [1.0, 0.5, 0.25], "intensity": 40.0,
         "range": 12.0},
        {"type": "spot", "name": "torch", "intensity": 100.0,
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
    ]}});
    let nodes = document["nodes"].as_array_mut().expect("nodes");
    nodes.push(json!({"translation": [1.0, 4.0, -2.0],
        "extensions": {"KHR_lights_punctual": {"light": 0}}}));
    // Turned 90 degrees down about X: its -Z shines along -Y.
    nodes.push(
        json!({"translation": [0.0, 6.0, 0.0], "rotation": about_x(-90.0),
        "extensions": {"KHR_lights_punctual": {"light": 1}}}),
    );
    let count = nodes.len();
    let roots = document["scenes"][0]["nodes"]
        .as_array_mut()
        .expect("roots");
    roots.push(json!(count - 2));
    roots.push(json!(count - 1));
    let scene = import_gltf_slice(
        document.to_string().as_bytes(),
        "lamps.gltf",
        &no_chunking(),
    )
    .expect("loads");
    assert_eq!(scene.lights.len(), 2, "{:?}", scene.lights);
    let lamp = &scene.lights[0];
    assert_eq!(lamp.name, "lamp");
    assert!(lamp.position.abs_diff_eq(Vec3::new(1.0, 4.0, -2.0), 1e-5));
    assert_eq!(lamp.kind, crate::scene::LightKind::Point);
    assert_eq!(lamp.color, [1.0, 0.5, 0.25]);
    assert_eq!((lamp.intensity, lamp.range), (40.0, Some(12.0)));
    let torch = &scene.lights[1];
    assert!(torch.position.abs_diff_eq(Vec3::new(0.0, 6.0, 0.0), 1e-5));
    let crate::scene::LightKind::Spot {
        direction,
        inner_cone_rad,
        outer_cone_rad,
    } = torch.kind
    else {
        panic!("a spot: {torch:?}");
    };
    assert!(direction.abs_diff_eq(Vec3::NEG_Y, 1e-5), "{direction}");
    assert_eq!((inner_cone_rad, outer_cone_rad), (0.2, 0.5));
    assert_eq!(torch.range, None);
    assert_eq!(
        scene.sun,
        Sun::default(),
        "no directional light: the default sun"
    );
}
