//! Every WGSL file in this crate parses and validates with naga, alone and as composed.

use std::path::Path;

fn validate(name: &str, source: &str) {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
}

fn wgsl_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir)
        .expect("source dir is readable")
        .flatten()
    {
        let path = entry.path();
        if path.is_dir() {
            wgsl_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            out.push(path);
        }
    }
}

#[test]
fn every_wgsl_file_validates() {
    let mut files = Vec::new();
    wgsl_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    assert!(
        files.len() >= 5,
        "expected the crate's shaders, found {files:?}"
    );
    for path in files {
        let source = std::fs::read_to_string(&path).expect("shader is readable");
        let name = path.display().to_string();
        // Files that use shared declarations are validated as the renderer composes them.
        let composed =
            if source.contains("Prepended with frame/instance.wgsl and frame/common.wgsl") {
                format!("{}\n{source}", crate::frame::scene_prelude())
            } else if source.contains("Prepended with frame/instance.wgsl") {
                format!("{}\n{source}", crate::frame::INSTANCE_WGSL)
            } else {
                source
            };
        validate(&name, &composed);
    }
}
