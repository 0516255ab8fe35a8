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

/// The files a shader's "Prepended with a.wgsl, b.wgsl and c.wgsl." comment names, joined.
fn prelude_of(source: &str) -> String {
    let Some(line) = source.lines().find(|l| l.contains("Prepended with ")) else {
        return String::new();
    };
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    line.split(|c: char| c.is_whitespace() || c == ',')
        .map(|w| w.trim_end_matches('.'))
        .filter(|w| Path::new(w).extension().is_some_and(|e| e == "wgsl"))
        .map(|w| {
            std::fs::read_to_string(src.join(w)).unwrap_or_else(|e| panic!("prelude {w}: {e}"))
        })
        .collect::<Vec<_>>()
        .join("\n")
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
        let composed = format!("{}\n{source}", prelude_of(&source));
        validate(&name, &composed);
    }
}
