//! glTF as exported today: `EXT_meshopt_compression` buffer views decoded with meshoptimizer
//! (the `meshopt` crate) into their fallback buffers before anything reads them, and
//! `KHR_mesh_quantization` accepted (primitives.rs reads its integer attributes). The `gltf`
//! crate rejects files that require either, so the document is parsed without validation,
//! the two are taken off its required list, and the rest is validated as before.

use serde_json::Value;

/// Required extensions this importer handles itself.
const HANDLED: [&str; 2] = ["EXT_meshopt_compression", "KHR_mesh_quantization"];

/// A decoded buffer never grows past this; a compressed view claiming more is an error.
const MAX_DECODED_BYTES: u64 = 1 << 30;

/// The document, validated after the extensions handled here are taken off its required list,
/// and the GLB binary chunk.
pub(super) fn parse(bytes: &[u8]) -> Result<(gltf::Document, Option<Vec<u8>>), String> {
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| e.to_string())?;
    let mut root = document.into_json();
    root.extensions_required
        .retain(|name| !HANDLED.contains(&name.as_str()));
    let document = gltf::Document::from_json(root).map_err(|e| e.to_string())?;
    Ok((document, blob))
}

/// Buffers that only stand in for meshopt-compressed data (`"fallback": true`): they have no
/// bytes of their own, and the decoded views fill them.
pub(super) fn is_fallback(buffer: &gltf::Buffer) -> bool {
    buffer
        .extensions()
        .and_then(|e| e.get("EXT_meshopt_compression"))
        .and_then(|e| e.get("fallback"))
        .and_then(Value::as_bool)
        .unwrap_or(false)
}

/// One compressed buffer view, as its extension object describes it.
struct Compressed {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: String,
    filter: String,
}

impl Compressed {
    fn from_view(view: &gltf::buffer::View) -> Option<Result<Self, String>> {
        let ext = view.extensions()?.get("EXT_meshopt_compression")?;
        let number = |key: &str| ext.get(key).and_then(Value::as_u64);
        let text = |key: &str, default: &str| {
            ext.get(key)
                .and_then(Value::as_str)
                .unwrap_or(default)
                .to_owned()
        };
        let parsed = (|| {
            let field = |key: &str| {
                number(key)
                    .and_then(|n| usize::try_from(n).ok())
                    .ok_or_else(|| format!("its '{key}' is missing or not a size"))
            };
            Ok(Self {
                buffer: field("buffer")?,
                offset: number("byteOffset").map_or(Ok(0), |_| field("byteOffset"))?,
                length: field("byteLength")?,
                stride: field("byteStride")?,
                count: field("count")?,
                mode: text("mode", ""),
                filter: text("filter", "NONE"),
            })
        })();
        Some(parsed)
    }
}

/// Decodes every compressed view into its place in its (fallback) buffer. Each error names the
/// buffer view and the problem.
pub(super) fn decode_views(
    document: &gltf::Document,
    buffers: &mut [Vec<u8>],
) -> Result<(), String> {
    for view in document.views() {
        let Some(parsed) = Compressed::from_view(&view) else {
            continue;
        };
        let bad = |reason: String| format!("buffer view {} (meshopt): {reason}", view.index());
        let c = parsed.map_err(bad)?;
        // Sizes are checked before meshoptimizer allocates anything.
        let size = (c.count as u64).checked_mul(c.stride as u64);
        if size != Some(view.length() as u64) {
            return Err(bad(format!(
                "{} elements of {} bytes do not fill the view's {} bytes",
                c.count,
                c.stride,
                view.length()
            )));
        }
        let end = view.offset() as u64 + view.length() as u64;
        if end > MAX_DECODED_BYTES {
            return Err(bad(format!(
                "it decodes to byte {end} of its buffer, beyond the {MAX_DECODED_BYTES}-byte limit"
            )));
        }
        let decoded = decode(&c, buffers).map_err(bad)?;
        let target = buffers
            .get_mut(view.buffer().index())
            .ok_or_else(|| bad("its buffer does not exist".into()))?;
        let end = view.offset() + view.length();
        if target.len() < end {
            target.resize(end, 0);
        }
        target[view.offset()..end].copy_from_slice(&decoded);
    }
    Ok(())
}

/// The view's bytes: `count` elements of `stride` bytes.
fn decode(c: &Compressed, buffers: &[Vec<u8>]) -> Result<Vec<u8>, String> {
    let source = buffers
        .get(c.buffer)
        .and_then(|b| b.get(c.offset..c.offset.checked_add(c.length)?))
        .ok_or_else(|| format!("its compressed bytes lie outside buffer {}", c.buffer))?;
    let mut bytes = match c.mode.as_str() {
        "ATTRIBUTES" => decode_attributes(source, c.count, c.stride).map_err(failed)?,
        "TRIANGLES" | "INDICES" => decode_indices(source, c)?,
        other => {
            return Err(format!(
                "its mode '{other}' is not one of ATTRIBUTES, TRIANGLES, INDICES"
            ));
        }
    };
    unfilter(&mut bytes, c)?;
    Ok(bytes)
}

#[allow(clippy::needless_pass_by_value)] // a `map_err` callback
fn failed(e: meshopt::Error) -> String {
    format!("meshoptimizer could not decode it ({e})")
}

/// Indices as 16- or 32-bit little-endian words (the extension's strides 2 and 4). The encoding
/// does not depend on the index size, so they are decoded as 32-bit and narrowed.
fn decode_indices(source: &[u8], c: &Compressed) -> Result<Vec<u8>, String> {
    let indices: Vec<u32> = if c.mode == "INDICES" {
        meshopt::decode_index_sequence(source, c.count).map_err(failed)?
    } else {
        meshopt::decode_index_buffer(source, c.count).map_err(failed)?
    };
    match c.stride {
        4 => Ok(indices.iter().flat_map(|i| i.to_le_bytes()).collect()),
        2 => indices
            .iter()
            .map(|&i| u16::try_from(i).map(u16::to_le_bytes))
            .collect::<Result<Vec<_>, _>>()
            .map(|words| words.concat())
            .map_err(|_| "a 16-bit index view holds an index above 65535".to_owned()),
        other => Err(format!(
            "indices take a stride of 2 or 4 bytes, not {other}"
        )),
    }
}

/// One vertex of `N` bytes, for meshoptimizer's vertex decoder (which takes the vertex size
/// from the element type).
#[derive(Clone, Copy)]
struct Vertex<const N: usize>([u8; N]);

impl<const N: usize> Default for Vertex<N> {
    fn default() -> Self {
        Self([0; N])
    }
}

fn decode_strided<const N: usize>(source: &[u8], count: usize) -> meshopt::Result<Vec<u8>> {
    let vertices: Vec<Vertex<N>> = meshopt::decode_vertex_buffer(source, count)?;
    Ok(vertices.iter().flat_map(|v| v.0).collect())
}

/// Vertex data of any stride the extension allows (a multiple of 4 up to 256 bytes).
fn decode_attributes(source: &[u8], count: usize, stride: usize) -> meshopt::Result<Vec<u8>> {
    macro_rules! by_stride {
        ($($n:literal)*) => {
            match stride {
                $($n => decode_strided::<$n>(source, count),)*
                _ => Err(meshopt::Error::Memory(
                    format!("a vertex stride of {stride} bytes is not a multiple of 4 up to 256")
                        .into(),
                )),
            }
        };
    }
    by_stride!(4 8 12 16 20 24 28 32 36 40 44 48 52 56 60 64 68 72 76 80 84 88 92 96 100 104 108
        112 116 120 124 128 132 136 140 144 148 152 156 160 164 168 172 176 180 184 188 192 196 200
        204 208 212 216 220 224 228 232 236 240 244 248 252 256)
}

/// Undoes the view's filter in place (the extension's OCTAHEDRAL, QUATERNION, EXPONENTIAL).
fn unfilter(bytes: &mut [u8], c: &Compressed) -> Result<(), String> {
    let wrong_stride = || {
        format!(
            "the {} filter does not take a stride of {}",
            c.filter, c.stride
        )
    };
    match (c.filter.as_str(), c.stride) {
        ("NONE", _) => {}
        ("OCTAHEDRAL", 4) => {
            let mut v: Vec<[i8; 4]> = bytes
                .chunks_exact(4)
                .map(|b| [b[0], b[1], b[2], b[3]].map(|x| i8::from_le_bytes([x])))
                .collect();
            meshopt::decode_filter_oct(&mut v);
            write_back(bytes, v.iter().flatten().map(|x| x.to_le_bytes()));
        }
        ("OCTAHEDRAL", 8) => {
            let mut v: Vec<[i16; 4]> = words16(bytes);
            meshopt::decode_filter_oct(&mut v);
            write_back(bytes, v.iter().flatten().map(|x| x.to_le_bytes()));
        }
        ("QUATERNION", 8) => {
            let mut v: Vec<[i16; 4]> = words16(bytes);
            meshopt::decode_filter_quat(&mut v);
            write_back(bytes, v.iter().flatten().map(|x| x.to_le_bytes()));
        }
        ("EXPONENTIAL", s) if s % 4 == 0 => {
            let mut v: Vec<[u32; 1]> = bytes
                .chunks_exact(4)
                .map(|b| [u32::from_le_bytes([b[0], b[1], b[2], b[3]])])
                .collect();
            meshopt::decode_filter_exp(&mut v);
            write_back(bytes, v.iter().flatten().map(|x| x.to_le_bytes()));
        }
        ("OCTAHEDRAL" | "QUATERNION" | "EXPONENTIAL", _) => return Err(wrong_stride()),
        (other, _) => return Err(format!("its filter '{other}' is not supported")),
    }
    Ok(())
}

fn words16(bytes: &[u8]) -> Vec<[i16; 4]> {
    bytes
        .chunks_exact(8)
        .map(|b| {
            let w = |i: usize| i16::from_le_bytes([b[2 * i], b[2 * i + 1]]);
            [w(0), w(1), w(2), w(3)]
        })
        .collect()
}

fn write_back<const K: usize>(bytes: &mut [u8], values: impl Iterator<Item = [u8; K]>) {
    for (chunk, value) in bytes.chunks_exact_mut(K).zip(values) {
        chunk.copy_from_slice(&value);
    }
}
