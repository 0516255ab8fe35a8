//! The bytes of a glTF file's buffers: the GLB binary chunk, base64 `data:` URIs and external
//! files inside the `.gltf`'s folder (never an absolute path, a `..` out of it or a link that
//! leads out; the declared length checked against the file before it is read). Each failure is
//! an [`ImportError`] that names the file. Images are never read.

use std::path::{Component, Path, PathBuf};

use super::ImportError;
use super::compression::is_fallback;

/// `gltf` subtracts the header size from the declared GLB length before checking it, which
/// panics on a length below 12; reject that here.
pub(super) fn check_glb_header(bytes: &[u8]) -> Result<(), String> {
    if bytes.starts_with(b"glTF")
        && let Some(&[a, b, c, d]) = bytes.get(8..12)
    {
        let declared_length = u32::from_le_bytes([a, b, c, d]);
        if declared_length < 12 {
            return Err(format!(
                "the GLB header declares a length of {declared_length} bytes"
            ));
        }
    }
    Ok(())
}

/// The bytes of every buffer, in document order.
pub(super) fn load_buffers(
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    path: &Path,
    base_dir: Option<&Path>,
) -> Result<Vec<Vec<u8>>, ImportError> {
    let bad_buffer = |index: usize, reason: String| ImportError::BadBuffer {
        path: path.to_owned(),
        index,
        reason,
    };
    document
        .buffers()
        .map(|buffer| {
            let index = buffer.index();
            // Filled by the meshopt-compressed views (compression.rs).
            if is_fallback(&buffer) {
                return Ok(Vec::new());
            }
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => blob
                    .take()
                    .ok_or_else(|| bad_buffer(index, "the GLB file has no binary chunk".into()))?,
                gltf::buffer::Source::Uri(uri) => {
                    read_buffer_uri(uri, (index, buffer.length()), path, base_dir)?
                }
            };
            if data.len() < buffer.length() {
                let reason = format!(
                    "it holds {} bytes but should hold {}",
                    data.len(),
                    buffer.length()
                );
                return Err(bad_buffer(index, reason));
            }
            Ok(data)
        })
        .collect()
}

/// Reads a buffer given by a `data:` URI or a path inside `base_dir` (the scene's folder),
/// which must hold at least `declared_length` bytes.
fn read_buffer_uri(
    uri: &str,
    (index, declared_length): (usize, usize),
    path: &Path,
    base_dir: Option<&Path>,
) -> Result<Vec<u8>, ImportError> {
    let bad_buffer = |reason: String| ImportError::BadBuffer {
        path: path.to_owned(),
        index,
        reason,
    };
    if uri.starts_with("data:") {
        let source = gltf::buffer::Source::Uri(uri);
        return gltf::buffer::Data::from_source(source, None)
            .map(|data| data.0)
            .map_err(|e| bad_buffer(format!("its data URI is not valid base64: {e}")));
    }
    if uri.contains(':') {
        // `file:` URIs name absolute paths, which a scene must not reach; others are remote.
        return Err(bad_buffer(format!(
            "the URI '{uri}' has a scheme; only data: URIs and paths inside the scene's folder \
             are read"
        )));
    }
    let relative =
        percent_decode(uri).ok_or_else(|| bad_buffer(format!("the URI '{uri}' is malformed")))?;
    let base_dir = base_dir.ok_or_else(|| {
        bad_buffer(format!(
            "it refers to the external file '{uri}', which cannot be loaded from memory"
        ))
    })?;
    let file_path = inside_folder(base_dir, &relative)
        .map_err(|why| bad_buffer(format!("the URI '{uri}' {why}")))?;
    let missing = |error| ImportError::MissingBuffer {
        path: path.to_owned(),
        uri: uri.to_owned(),
        resolved: file_path.clone(),
        error,
    };
    // The declared length is checked against the file before anything is allocated.
    let on_disk = std::fs::metadata(&file_path).map_err(missing)?.len();
    if on_disk < declared_length as u64 {
        return Err(bad_buffer(format!(
            "it declares {declared_length} bytes but '{uri}' holds {on_disk}"
        )));
    }
    std::fs::read(&file_path).map_err(missing)
}

/// `relative` (a decoded URI path) resolved in `base_dir`, or why it may not be read: it is
/// absolute, climbs out with `..`, or leads out through a symbolic link.
fn inside_folder(base_dir: &Path, relative: &str) -> Result<PathBuf, String> {
    let relative_path = Path::new(relative);
    if relative_path.has_root() || relative.starts_with('/') || relative.starts_with('\\') {
        return Err("is an absolute path; buffers must lie inside the scene's folder".into());
    }
    let mut depth = 0usize;
    for part in relative_path.components() {
        match part {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth > 0 => depth -= 1,
            _ => return Err("leads outside the scene's folder".into()),
        }
    }
    let joined = base_dir.join(relative_path);
    // Symbolic links may point anywhere: compare the real paths where the file exists (a
    // missing file is reported as missing by the caller).
    let base_dir = if base_dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        base_dir
    };
    if let (Ok(real_base), Ok(real_file)) = (base_dir.canonicalize(), joined.canonicalize())
        && !real_file.starts_with(&real_base)
    {
        return Err(format!(
            "leads outside the scene's folder (through a link, to {})",
            real_file.display()
        ));
    }
    Ok(joined)
}

/// Decodes `%XX` escapes in a relative URI; `None` when an escape or the result is malformed.
pub(super) fn percent_decode(uri: &str) -> Option<String> {
    let mut bytes = Vec::with_capacity(uri.len());
    let mut rest = uri.as_bytes();
    while let Some((&first, tail)) = rest.split_first() {
        if first == b'%' {
            let hex = std::str::from_utf8(tail.get(..2)?).ok()?;
            bytes.push(u8::from_str_radix(hex, 16).ok()?);
            rest = &tail[2..];
        } else {
            bytes.push(first);
            rest = tail;
        }
    }
    String::from_utf8(bytes).ok()
}
