//! Every shader the renderer builds parses and validates with naga, composed by the same
//! functions the renderer calls; every WGSL file of the crate is part of one of them; and the
//! constants that WGSL and Rust both name agree.

use std::collections::HashSet;

use crate::scene_gpu::gpu_data::{FLAG_CASTER, FLAG_DYNAMIC, FLAG_RECEIVER};
use crate::view::gpu_data::{OVERLAY_CASTERS, OVERLAY_VIEWS};

/// Every composed shader of the renderer: (label, WGSL).
fn composed_shaders() -> Vec<(String, String)> {
    let light_wgsl = crate::shadow_map::LIGHT_WGSL;
    let mut shaders: Vec<(String, String)> = crate::culling::shader_sources()
        .into_iter()
        .map(|(label, source)| (label.to_owned(), source))
        .collect();
    shaders.extend([
        (
            "Frame::camera_shader".to_owned(),
            crate::frame::camera_shader_source(light_wgsl, true),
        ),
        (
            "Frame::camera_shader (no early depth test)".to_owned(),
            crate::frame::camera_shader_source(light_wgsl, false),
        ),
        (
            "Visibility::shader".to_owned(),
            crate::view::visibility_shader_source(),
        ),
        (
            "ShadowMap::shader".to_owned(),
            crate::shadow_map::maps::shader_source(),
        ),
        (
            "LightInset".to_owned(),
            crate::overlays::light_inset::shader_source(),
        ),
        (
            "ObserverLines".to_owned(),
            crate::overlays::observer::shader_source(),
        ),
        (
            "Truth::light_at_points".to_owned(),
            crate::truth::shader_source(light_wgsl),
        ),
        (
            "HeatMap".to_owned(),
            crate::metrics::heat_map_shader_source(),
        ),
    ]);
    // Shadow volumes: their passes, and the shading and truth passes with their light term.
    let volumes = crate::volumes::LIGHT_WGSL;
    shaders.extend(crate::volumes::shader_sources());
    shaders.extend([
        (
            "Frame::camera_shader (volumes)".to_owned(),
            crate::frame::camera_shader_source(volumes, true),
        ),
        (
            "Truth::light_at_points (volumes)".to_owned(),
            crate::truth::shader_source(volumes),
        ),
    ]);
    // Many lights: the multiview and atlas paths, culling and the culled draws, and the
    // passes with their light term.
    let layered = crate::layered::LIGHT_WGSL;
    shaders.extend(
        crate::layered::culled_sources()
            .into_iter()
            .map(|(label, source)| (label.to_owned(), source)),
    );
    shaders.extend([
        (
            "Layered::multiview".to_owned(),
            crate::layered::multiview_source(),
        ),
        ("Layered::atlas".to_owned(), crate::layered::atlas_source()),
        (
            "Layered::multiview_probe".to_owned(),
            crate::layered::probe_source(),
        ),
        ("Layered::cull".to_owned(), crate::layered::cull_source()),
        (
            "Layered::traditional".to_owned(),
            crate::layered::traditional_source(),
        ),
        (
            "Frame::camera_shader (lights)".to_owned(),
            crate::frame::camera_shader_source(layered, true),
        ),
        (
            "Truth::light_at_points (lights)".to_owned(),
            crate::truth::shader_source(layered),
        ),
    ]);
    // Virtual maps: the page table, marking, the cull and the page draws, and the passes
    // with their light term.
    let virtual_maps = crate::virtual_maps::LIGHT_WGSL;
    shaders.extend(crate::virtual_maps::shader_sources());
    shaders.extend([
        (
            "Frame::camera_shader (virtual)".to_owned(),
            crate::frame::camera_shader_source(virtual_maps, true),
        ),
        (
            "Truth::light_at_points (virtual)".to_owned(),
            crate::truth::shader_source(virtual_maps),
        ),
    ]);
    shaders
}

fn validate(name: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    module
}

/// The value of the named `u32` constant of `module`, if it has one.
fn u32_constant(module: &naga::Module, name: &str) -> Option<u32> {
    let (_, constant) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))?;
    match module.global_expressions[constant.init] {
        naga::Expression::Literal(naga::Literal::U32(v)) => Some(v),
        naga::Expression::Literal(naga::Literal::AbstractInt(v)) => u32::try_from(v).ok(),
        _ => None,
    }
}

#[test]
fn every_composed_shader_validates() {
    let shaders = composed_shaders();
    assert!(
        shaders.len() >= 9,
        "expected every shader, found {}",
        shaders.len()
    );
    for (name, source) in &shaders {
        validate(name, source);
    }
}

#[test]
fn every_wgsl_file_is_part_of_a_shader() {
    let composed: Vec<String> = composed_shaders().into_iter().map(|(_, s)| s).collect();
    let used: HashSet<&str> = crate::shaders::files()
        .filter(|path| {
            let marker = format!("// ---- {path}\n");
            composed.iter().any(|s| s.contains(&marker))
        })
        .collect();
    let unused: Vec<&str> = crate::shaders::files()
        .filter(|p| !used.contains(p))
        .collect();
    assert!(unused.is_empty(), "files no shader uses: {unused:?}");
}

#[test]
fn constants_named_on_both_sides_agree() {
    let shaders = composed_shaders();
    let camera = shaders
        .iter()
        .find(|(name, _)| name == "Frame::camera_shader")
        .map(|(name, source)| validate(name, source))
        .expect("the camera shader is composed");
    for (name, value) in [
        ("FLAG_CASTER", FLAG_CASTER),
        ("FLAG_RECEIVER", FLAG_RECEIVER),
        ("FLAG_DYNAMIC", FLAG_DYNAMIC),
        ("OVERLAY_CASTERS", OVERLAY_CASTERS),
        ("OVERLAY_VIEWS", OVERLAY_VIEWS),
        ("OUTCOME_RENDERED", crate::culling::codes::OUTCOME_RENDERED),
    ] {
        assert_eq!(u32_constant(&camera, name), Some(value), "{name}");
    }
    let volumes = shaders
        .iter()
        .find(|(name, _)| name == "volumes/draw.wgsl")
        .map(|(name, source)| validate(name, source))
        .expect("the volumes' draw shader is composed");
    assert_eq!(
        u32_constant(&volumes, "CAP_RECORDS"),
        Some(crate::volumes::CAP_RECORDS)
    );
}
