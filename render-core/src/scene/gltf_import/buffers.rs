//! The bytes of a glTF file's buffers: the GLB binary chunk, base64 `data:` URIs and external
//! files next to the `.gltf`. Each failure is an [`ImportError`] that names the file.

use std::path::{Path, PathBuf};

use super::ImportError;

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
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => blob
                    .take()
                    .ok_or_else(|| bad_buffer(index, "the GLB file has no binary chunk".into()))?,
                gltf::buffer::Source::Uri(uri) => read_buffer_uri(uri, index, path, base_dir)?,
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

/// Reads a buffer given by a `data:` URI, a `file:` URI or a path relative to `base_dir`.
fn read_buffer_uri(
    uri: &str,
    index: usize,
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
    let file_path = if let Some(absolute) = uri
        .strip_prefix("file://")
        .or_else(|| uri.strip_prefix("file:"))
    {
        PathBuf::from(absolute)
    } else if uri.contains(':') {
        return Err(bad_buffer(format!(
            "the URI '{uri}' uses a scheme that is not supported"
        )));
    } else {
        let relative = percent_decode(uri)
            .ok_or_else(|| bad_buffer(format!("the URI '{uri}' is malformed")))?;
        let base_dir = base_dir.ok_or_else(|| {
            bad_buffer(format!(
                "it refers to the external file '{uri}', which cannot be loaded from memory"
            ))
        })?;
        base_dir.join(relative)
    };
    std::fs::read(&file_path).map_err(|error| ImportError::MissingBuffer {
        path: path.to_owned(),
        uri: uri.to_owned(),
        resolved: file_path,
        error,
    })
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
