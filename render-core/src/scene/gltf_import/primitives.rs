//! One glTF primitive as a triangle mesh: its accessors checked before `gltf`'s reader trusts
//! them, strips and fans turned into lists, and triangles with non-finite positions dropped.

use glam::Vec3;
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::{Mode, Semantic};

use super::super::Mesh;
use super::super::chunking::compact_vertices;

/// The primitive as a triangle mesh named `name`, without unused vertices and without triangles
/// that touch non-finite positions. Repairs add to `warnings`, prefixed by `context`.
pub(super) fn read_triangle_mesh(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    name: String,
    context: &str,
    warnings: &mut Vec<String>,
) -> Result<Mesh, String> {
    let positions = read_positions(primitive, buffers)?;
    let vertex_order = read_vertex_order(primitive, buffers, positions.len())?;
    if primitive.mode() == Mode::Triangles && vertex_order.len() % 3 != 0 {
        warnings.push(format!(
            "{context}: {} trailing indices do not make a triangle; ignored",
            vertex_order.len() % 3
        ));
    }
    let indices = triangle_list(primitive.mode(), &vertex_order);
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(format!(
            "vertex index {bad} is out of range ({} vertices)",
            positions.len()
        ));
    }
    let normals = match read_normals(primitive, buffers, positions.len()) {
        Ok(normals) => normals,
        Err(reason) => {
            warnings.push(format!("{context}: normals recomputed: {reason}"));
            None
        }
    };

    let triangle_count = indices.len() / 3;
    let finite_indices: Vec<u32> = indices
        .chunks_exact(3)
        .filter(|triangle| triangle.iter().all(|&i| positions[i as usize].is_finite()))
        .flatten()
        .copied()
        .collect();
    let dropped = triangle_count - finite_indices.len() / 3;
    if finite_indices.is_empty() {
        return Err(if triangle_count == 0 {
            "it has no triangles".to_owned()
        } else {
            "every triangle has a non-finite vertex position".to_owned()
        });
    }
    if dropped > 0 {
        warnings.push(format!(
            "{context}: {dropped} of {triangle_count} triangles dropped: they touch non-finite \
             vertex positions"
        ));
    }
    let (positions, normals, indices) = compact_vertices(
        &positions,
        normals.as_deref().unwrap_or_default(),
        &finite_indices,
    );
    Ok(Mesh::new(name, positions, normals, indices))
}

fn read_positions(primitive: &gltf::Primitive, buffers: &[Vec<u8>]) -> Result<Vec<Vec3>, String> {
    let accessor = primitive
        .get(&Semantic::Positions)
        .ok_or("it has no POSITION attribute")?;
    check_accessor(&accessor, &QUANTIZED, Dimensions::Vec3, buffers)
        .map_err(|reason| format!("its POSITION accessor {reason}"))?;
    let positions = read_vec3s(&accessor, buffers).ok_or("its positions cannot be read")?;
    if u32::try_from(positions.len()).is_err() {
        return Err(format!(
            "it has {} vertices, more than 32-bit indices can address",
            positions.len()
        ));
    }
    Ok(positions)
}

/// The primitive's indices, or `0..vertex_count` when it has none.
fn read_vertex_order(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    vertex_count: usize,
) -> Result<Vec<u32>, String> {
    let Some(accessor) = primitive.indices() else {
        return Ok((0..vertex_count as u32).collect());
    };
    check_accessor(
        &accessor,
        &[DataType::U8, DataType::U16, DataType::U32],
        Dimensions::Scalar,
        buffers,
    )
    .map_err(|reason| format!("its index accessor {reason}"))?;
    let reader = primitive.reader(|buffer| buffers.get(buffer.index()).map(Vec::as_slice));
    Ok(reader
        .read_indices()
        .ok_or("its indices cannot be read")?
        .into_u32()
        .collect())
}

/// Unit normals from the file; `Ok(None)` when it has none, `Err` when they are unusable.
fn read_normals(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    vertex_count: usize,
) -> Result<Option<Vec<Vec3>>, String> {
    let Some(accessor) = primitive.get(&Semantic::Normals) else {
        return Ok(None);
    };
    check_accessor(
        &accessor,
        &[DataType::F32, DataType::I8, DataType::I16],
        Dimensions::Vec3,
        buffers,
    )
    .map_err(|reason| format!("the NORMAL accessor {reason}"))?;
    if accessor.count() != vertex_count {
        return Err(format!(
            "there are {} normals for {vertex_count} vertices",
            accessor.count()
        ));
    }
    let normals = read_vec3s(&accessor, buffers).ok_or("the normals cannot be read")?;
    let unit_normals: Option<Vec<Vec3>> = normals.into_iter().map(Vec3::try_normalize).collect();
    unit_normals
        .map(Some)
        .ok_or_else(|| "some normals are zero or not finite".to_owned())
}

/// The component types of a position: floats, or with `KHR_mesh_quantization` integers.
const QUANTIZED: [DataType; 5] = [
    DataType::F32,
    DataType::I8,
    DataType::U8,
    DataType::I16,
    DataType::U16,
];

/// A checked vec3 accessor's elements as floats: as stored, or for the integer types of
/// `KHR_mesh_quantization` their value, divided by the type's largest when normalized
/// (glTF 2.0, 3.11: signed values clamp at -1).
fn read_vec3s(accessor: &gltf::Accessor, buffers: &[Vec<u8>]) -> Option<Vec<Vec3>> {
    fn read<T: gltf::accessor::Item + Copy>(
        accessor: &gltf::Accessor,
        buffers: &[Vec<u8>],
        to_f32: impl Fn(T) -> f32,
    ) -> Option<Vec<Vec3>> {
        let get = |buffer: gltf::Buffer| buffers.get(buffer.index()).map(Vec::as_slice);
        let elements = gltf::accessor::Iter::<[T; 3]>::new(accessor.clone(), get)?;
        Some(elements.map(|v| Vec3::from(v.map(&to_f32))).collect())
    }
    let normalized = accessor.normalized();
    let scale = |value: f32, largest: f32| {
        if normalized {
            (value / largest).max(-1.0)
        } else {
            value
        }
    };
    match accessor.data_type() {
        DataType::F32 => read::<f32>(accessor, buffers, |x| x),
        DataType::I8 => read::<i8>(accessor, buffers, |x| scale(f32::from(x), 127.0)),
        DataType::U8 => read::<u8>(accessor, buffers, |x| scale(f32::from(x), 255.0)),
        DataType::I16 => read::<i16>(accessor, buffers, |x| scale(f32::from(x), 32767.0)),
        DataType::U16 => read::<u16>(accessor, buffers, |x| scale(f32::from(x), 65535.0)),
        DataType::U32 => None,
    }
}

/// Checks what `gltf`'s reader assumes (and would panic or silently truncate on otherwise): the
/// element type, a non-empty dense accessor, and every element inside its view and buffer.
fn check_accessor(
    accessor: &gltf::Accessor,
    data_types: &[DataType],
    dimensions: Dimensions,
    buffers: &[Vec<u8>],
) -> Result<(), String> {
    let index = accessor.index();
    if !data_types.contains(&accessor.data_type()) || accessor.dimensions() != dimensions {
        let found = (accessor.data_type(), accessor.dimensions());
        return Err(format!(
            "{index} has type {found:?}, expected {dimensions:?} of {data_types:?}"
        ));
    }
    if accessor.sparse().is_some() {
        return Err(format!(
            "{index} uses sparse storage, which is not supported"
        ));
    }
    let view = accessor
        .view()
        .ok_or_else(|| format!("{index} has no buffer view"))?;
    if accessor.count() == 0 {
        return Err(format!("{index} is empty"));
    }
    let element_size = accessor.size();
    let stride = view.stride().unwrap_or(element_size);
    if stride < element_size {
        return Err(format!(
            "{index} has a stride of {stride} bytes for {element_size}-byte elements"
        ));
    }
    let buffer_length = buffers.get(view.buffer().index()).map_or(0, Vec::len);
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|end| end > buffer_length)
    {
        return Err(format!(
            "{index} uses buffer view {}, which runs past the end of its buffer",
            view.index()
        ));
    }
    let accessor_end = (accessor.count() - 1)
        .checked_mul(stride)
        .and_then(|last_start| last_start.checked_add(accessor.offset()))
        .and_then(|last_start| last_start.checked_add(element_size));
    if accessor_end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "{index} runs past the end of buffer view {}",
            view.index()
        ));
    }
    Ok(())
}

/// Three indices per triangle from a triangle list, strip or fan (glTF 2.0 spec, section 3.7.2.1
/// "Topology Types"); other modes give nothing.
fn triangle_list(mode: Mode, order: &[u32]) -> Vec<u32> {
    let n = order.len();
    match mode {
        Mode::Triangles => order[..n / 3 * 3].to_vec(),
        // Every other strip triangle swaps two vertices to keep the winding.
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .flat_map(|i| {
                let odd = i % 2;
                [order[i], order[i + 1 + odd], order[i + 2 - odd]]
            })
            .collect(),
        Mode::TriangleFan => (0..n.saturating_sub(2))
            .flat_map(|i| [order[i + 1], order[i + 2], order[0]])
            .collect(),
        _ => Vec::new(),
    }
}
