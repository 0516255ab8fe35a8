//! WGSL composition, in one place: a shader is a file of this crate with the files it names in
//! `#import folder/file.wgsl` lines placed before it, each once, depth first. Files that Rust
//! writes (constants generated from Rust enums, a technique's light term) are passed in as
//! virtual files. The renderer and the naga validation test compose through [`compose`], so
//! what is validated is what runs.

use std::fmt::Write as _;

/// Every WGSL file of the crate, by its path under `src/`.
const FILES: &[(&str, &str)] = &[
    (
        "scene_gpu/instance.wgsl",
        include_str!("scene_gpu/instance.wgsl"),
    ),
    ("view/common.wgsl", include_str!("view/common.wgsl")),
    (
        "view/camera_vertex.wgsl",
        include_str!("view/camera_vertex.wgsl"),
    ),
    ("view/visibility.wgsl", include_str!("view/visibility.wgsl")),
    (
        "shadow_view/views.wgsl",
        include_str!("shadow_view/views.wgsl"),
    ),
    (
        "shadow_view/lookup.wgsl",
        include_str!("shadow_view/lookup.wgsl"),
    ),
    (
        "culling/cull_common.wgsl",
        include_str!("culling/cull_common.wgsl"),
    ),
    ("culling/cull.wgsl", include_str!("culling/cull.wgsl")),
    ("culling/masks.wgsl", include_str!("culling/masks.wgsl")),
    (
        "culling/receivers.wgsl",
        include_str!("culling/receivers.wgsl"),
    ),
    ("culling/pyramid.wgsl", include_str!("culling/pyramid.wgsl")),
    (
        "culling/footprints.wgsl",
        include_str!("culling/footprints.wgsl"),
    ),
    ("culling/widen.wgsl", include_str!("culling/widen.wgsl")),
    (
        "shadow_map/shadow_depth.wgsl",
        include_str!("shadow_map/shadow_depth.wgsl"),
    ),
    (
        "shadow_map/light.wgsl",
        include_str!("shadow_map/light.wgsl"),
    ),
    ("metrics/measure.wgsl", include_str!("metrics/measure.wgsl")),
    (
        "metrics/heat_map.wgsl",
        include_str!("metrics/heat_map.wgsl"),
    ),
    (
        "overlays/outcome_colours.wgsl",
        include_str!("overlays/outcome_colours.wgsl"),
    ),
    (
        "overlays/light_inset.wgsl",
        include_str!("overlays/light_inset.wgsl"),
    ),
    (
        "overlays/observer_lines.wgsl",
        include_str!("overlays/observer_lines.wgsl"),
    ),
    ("truth/at_points.wgsl", include_str!("truth/at_points.wgsl")),
    ("frame/camera.wgsl", include_str!("frame/camera.wgsl")),
    ("volumes/common.wgsl", include_str!("volumes/common.wgsl")),
    ("volumes/find.wgsl", include_str!("volumes/find.wgsl")),
    ("volumes/records.wgsl", include_str!("volumes/records.wgsl")),
    (
        "volumes/point_light.wgsl",
        include_str!("volumes/point_light.wgsl"),
    ),
    (
        "volumes/footprint.wgsl",
        include_str!("volumes/footprint.wgsl"),
    ),
    ("volumes/grid.wgsl", include_str!("volumes/grid.wgsl")),
    (
        "volumes/shadowing.wgsl",
        include_str!("volumes/shadowing.wgsl"),
    ),
    (
        "volumes/big_casters.wgsl",
        include_str!("volumes/big_casters.wgsl"),
    ),
    ("volumes/draw.wgsl", include_str!("volumes/draw.wgsl")),
    (
        "volumes/strips_clipped.wgsl",
        include_str!("volumes/strips_clipped.wgsl"),
    ),
    (
        "volumes/strips_whole.wgsl",
        include_str!("volumes/strips_whole.wgsl"),
    ),
    ("volumes/light.wgsl", include_str!("volumes/light.wgsl")),
    ("layered/light.wgsl", include_str!("layered/light.wgsl")),
    (
        "layered/multiview.wgsl",
        include_str!("layered/multiview.wgsl"),
    ),
    ("layered/atlas.wgsl", include_str!("layered/atlas.wgsl")),
    (
        "virtual_maps/pages.wgsl",
        include_str!("virtual_maps/pages.wgsl"),
    ),
    (
        "virtual_maps/tables.wgsl",
        include_str!("virtual_maps/tables.wgsl"),
    ),
    (
        "virtual_maps/allocate.wgsl",
        include_str!("virtual_maps/allocate.wgsl"),
    ),
    (
        "virtual_maps/mark.wgsl",
        include_str!("virtual_maps/mark.wgsl"),
    ),
    (
        "virtual_maps/cull.wgsl",
        include_str!("virtual_maps/cull.wgsl"),
    ),
    (
        "virtual_maps/draw.wgsl",
        include_str!("virtual_maps/draw.wgsl"),
    ),
    (
        "virtual_maps/occlusion.wgsl",
        include_str!("virtual_maps/occlusion.wgsl"),
    ),
    (
        "virtual_maps/light.wgsl",
        include_str!("virtual_maps/light.wgsl"),
    ),
    (
        "virtual_maps/overlay.wgsl",
        include_str!("virtual_maps/overlay.wgsl"),
    ),
    ("layered/tile.wgsl", include_str!("layered/tile.wgsl")),
    ("layered/load.wgsl", include_str!("layered/load.wgsl")),
    (
        "layered/traditional.wgsl",
        include_str!("layered/traditional.wgsl"),
    ),
    ("layered/cull.wgsl", include_str!("layered/cull.wgsl")),
    ("layered/culled.wgsl", include_str!("layered/culled.wgsl")),
    (
        "layered/culled_multiview.wgsl",
        include_str!("layered/culled_multiview.wgsl"),
    ),
    (
        "layered/culled_atlas.wgsl",
        include_str!("layered/culled_atlas.wgsl"),
    ),
    (
        "layered/multiview_probe.wgsl",
        include_str!("layered/multiview_probe.wgsl"),
    ),
    (
        "volumes/fill_heat.wgsl",
        include_str!("volumes/fill_heat.wgsl"),
    ),
];

/// A file that Rust writes, named like a file of the crate (`culling/codes.wgsl`).
pub(crate) type VirtualFile<'a> = (&'static str, &'a str);

/// The source of the file at `path`, from the crate's files or `virtual_files`.
fn source_of<'a>(path: &str, virtual_files: &[VirtualFile<'a>]) -> Option<&'a str> {
    virtual_files
        .iter()
        .find(|(p, _)| *p == path)
        .map(|(_, s)| *s)
        .or_else(|| FILES.iter().find(|(p, _)| *p == path).map(|(_, s)| *s))
}

/// The `#import` targets of a source, in order.
fn imports(source: &str) -> impl Iterator<Item = &str> {
    source
        .lines()
        .filter_map(|l| l.trim().strip_prefix("#import "))
        .map(str::trim)
}

/// `root` with everything it imports, each file once, imports first. An import that names no
/// file is a bug the validation test catches; here it is logged and left as a comment, which
/// then fails to compile with a message naming it.
pub(crate) fn compose<'a>(root: &'a str, virtual_files: &[VirtualFile<'a>]) -> String {
    let mut out = String::new();
    let mut done = Vec::new();
    append(root, virtual_files, &mut done, &mut out);
    out
}

fn append<'a>(
    path: &'a str,
    virtual_files: &[VirtualFile<'a>],
    done: &mut Vec<&'a str>,
    out: &mut String,
) {
    if done.contains(&path) {
        return;
    }
    done.push(path);
    let Some(source) = source_of(path, virtual_files) else {
        log::error!("WGSL import '{path}' names no file");
        let _ = writeln!(out, "missing import {path}");
        return;
    };
    for import in imports(source) {
        append(import, virtual_files, done, out);
    }
    let _ = writeln!(out, "// ---- {path}");
    for line in source.lines() {
        if !line.trim_start().starts_with("#import ") {
            out.push_str(line);
        }
        out.push('\n');
    }
}

/// Every file of the crate, for the validation test.
#[cfg(test)]
pub(crate) fn files() -> impl Iterator<Item = &'static str> {
    FILES.iter().map(|(p, _)| *p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_import_names_a_file_and_every_file_is_listed() {
        let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut on_disk = Vec::new();
        wgsl_files(&src, &src, &mut on_disk);
        for path in &on_disk {
            assert!(
                FILES.iter().any(|(p, _)| p == path),
                "{path} is not listed in shaders.rs"
            );
        }
        for (path, source) in FILES {
            let on_disk = std::fs::read_to_string(src.join(path)).expect("listed file exists");
            assert_eq!(&on_disk, source, "{path}");
            for import in imports(source) {
                // volumes/strips.wgsl: one of the strips files, as the adapter can clip.
                let generated = ["culling/codes.wgsl", "palette.wgsl", "volumes/strips.wgsl"]
                    .contains(&import)
                    || import.starts_with("technique/");
                assert!(
                    generated || FILES.iter().any(|(p, _)| *p == import),
                    "{path} imports {import}, which is not a file of the crate"
                );
            }
        }
    }

    fn wgsl_files(root: &std::path::Path, dir: &std::path::Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir)
            .expect("source dir is readable")
            .flatten()
        {
            let path = entry.path();
            if path.is_dir() {
                wgsl_files(root, &path, out);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                let relative = path.strip_prefix(root).expect("under src");
                out.push(relative.to_string_lossy().replace('\\', "/"));
            }
        }
    }

    #[test]
    fn imports_come_first_and_once() {
        let composed = compose(
            "a.wgsl",
            &[
                ("a.wgsl", "#import b.wgsl\n#import c.wgsl\nfn a() {}"),
                ("b.wgsl", "#import c.wgsl\nfn b() {}"),
                ("c.wgsl", "fn c() {}"),
            ],
        );
        let at = |s| composed.find(s).expect("present");
        assert!(at("fn c()") < at("fn b()") && at("fn b()") < at("fn a()"));
        assert_eq!(composed.matches("fn c()").count(), 1);
        assert!(!composed.contains("#import"));
    }
}
