//! Edge adjacency for shadow volumes, built once per mesh: every edge with the triangle that
//! winds it one way and, where the mesh is closed there, the triangle that winds it back.
//! Corners are welded by position (a mesh splits vertices for normals), so a box of 24
//! vertices is closed. An edge with one triangle, with more than two, or with two that wind
//! it the same way is kept once per triangle with no opposite, and the mesh is not closed:
//! its triangles then cast from both sides (Bergeron's generalisation), never dropped.
//!
//! Per frame and light, an edge's quad is extruded `multiplicity` times (`volumes.wgsl`
//! does the same on the GPU): the sign of each of its triangles' facing, the opposite one
//! negated, so edges between two lit (or two unlit) triangles of a closed mesh cancel.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// An edge's `opposite` when no triangle winds it back.
pub const NO_FACE: u32 = u32::MAX;

/// One edge: corners `a` to `b` as triangle `face` winds them (vertex and triangle indices
/// of the mesh), and the triangle that winds it from `b` to `a`, or [`NO_FACE`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct Edge {
    pub a: u32,
    pub b: u32,
    pub face: u32,
    pub opposite: u32,
}

/// A mesh's edges and whether it is closed (every edge wound once each way).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MeshEdges {
    pub edges: Vec<Edge>,
    pub closed: bool,
    /// Edges with one triangle.
    pub open_edges: u32,
    /// Edges with more than two triangles, or two wound the same way.
    pub non_manifold_edges: u32,
    /// Triangles left out for having two corners at one position (they cast nothing).
    pub degenerate_triangles: u32,
    /// Closed and convex (every corner on or behind every triangle's plane; meshes of over
    /// [`CONVEX_TEST_TRIANGLES`] triangles are not tested and count as not convex): a point of
    /// its surface facing the light is never in its own shadow.
    pub convex: bool,
}

/// The most triangles whose mesh is tested for convexity.
pub const CONVEX_TEST_TRIANGLES: usize = 1024;

/// The edges of the triangle list `indices` over `positions`.
pub fn mesh_edges(positions: &[Vec3], indices: &[u32]) -> MeshEdges {
    let welded = weld(positions);
    let corner = |i: u32| welded.get(i as usize).copied().unwrap_or(u32::MAX);
    // Each triangle's three half-edges, keyed by their welded ends, low first.
    let mut halves: Vec<((u32, u32), Edge)> = Vec::with_capacity(indices.len());
    let mut out = MeshEdges::default();
    for (face, tri) in (0..).zip(indices.chunks_exact(3)) {
        let w = [corner(tri[0]), corner(tri[1]), corner(tri[2])];
        if w[0] == w[1] || w[1] == w[2] || w[2] == w[0] || w.contains(&u32::MAX) {
            out.degenerate_triangles += 1;
            continue;
        }
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let (wa, wb) = (w[k], w[(k + 1) % 3]);
            let edge = Edge {
                a,
                b,
                face,
                opposite: NO_FACE,
            };
            halves.push(((wa.min(wb), wa.max(wb)), edge));
        }
    }
    halves.sort_unstable_by_key(|(key, e)| (*key, e.face));
    out.closed = out.degenerate_triangles == 0;
    let mut start = 0;
    while start < halves.len() {
        let key = halves[start].0;
        let end = start + halves[start..].partition_point(|(k, _)| *k == key);
        let group = &halves[start..end];
        let forward = |e: &Edge| welded[e.a as usize] == key.0;
        match group {
            [(_, first), (_, second)] if forward(first) != forward(second) => {
                out.edges.push(Edge {
                    opposite: second.face,
                    ..*first
                });
            }
            _ => {
                out.closed = false;
                if group.len() == 1 {
                    out.open_edges += 1;
                } else {
                    out.non_manifold_edges += 1;
                }
                out.edges.extend(group.iter().map(|(_, e)| *e));
            }
        }
        start = end;
    }
    out.convex = out.closed && is_convex(positions, indices);
    out
}

/// Whether every corner of the triangles `indices` lies on or behind (within a millionth of
/// the mesh's size) every triangle's plane; false past [`CONVEX_TEST_TRIANGLES`].
fn is_convex(positions: &[Vec3], indices: &[u32]) -> bool {
    if indices.len() / 3 > CONVEX_TEST_TRIANGLES {
        return false;
    }
    let at = |i: u32| positions.get(i as usize).copied();
    let used: Option<Vec<Vec3>> = indices.iter().map(|&i| at(i)).collect();
    let Some(used) = used else {
        return false;
    };
    let (lo, hi) = used.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| {
        (lo.min(*p), hi.max(*p))
    });
    let slack = (hi - lo).length() * 1e-6;
    used.chunks_exact(3).all(|t| {
        let Some(n) = (t[1] - t[0]).cross(t[2] - t[0]).try_normalize() else {
            return true;
        };
        used.iter().all(|p| n.dot(*p - t[0]) <= slack)
    })
}

/// One id per position, equal for equal positions (bit for bit; `-0.0` as `0.0`).
fn weld(positions: &[Vec3]) -> Vec<u32> {
    let key = |p: Vec3| (p + Vec3::ZERO).to_array().map(f32::to_bits);
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.sort_unstable_by_key(|&i| key(positions[i as usize]));
    let mut id = vec![0; positions.len()];
    let mut current = 0;
    for (n, &i) in order.iter().enumerate() {
        if n == 0 || key(positions[order[n - 1] as usize]) != key(positions[i as usize]) {
            current = i;
        }
        id[i as usize] = current;
    }
    id
}

/// How a triangle casts towards the light: +1 lit (its front faces the light), -1 unlit, and
/// in a closed mesh 0 for unlit ones (the lit side's volume holds them).
pub fn face_sign(facing_light: bool, closed: bool) -> i32 {
    match (facing_light, closed) {
        (true, _) => 1,
        (false, true) => 0,
        (false, false) => -1,
    }
}

/// How many times the edge's quad is extruded, and which way (the sign: as `face` winds it):
/// its triangle's sign less its opposite's.
pub fn multiplicity(face: i32, opposite: Option<i32>) -> i32 {
    face - opposite.unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube as renderers build it: four vertices per side, 24 in all, wound
    /// counter-clockwise seen from outside.
    fn cube() -> (Vec<Vec3>, Vec<u32>) {
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let mut n = Vec3::ZERO;
                n[axis] = sign;
                let (u, v) = (
                    n.any_orthonormal_vector(),
                    n.cross(n.any_orthonormal_vector()),
                );
                let base = positions.len() as u32;
                for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    positions.push((n + u * su + v * sv) * 0.5);
                }
                let tri = [0, 1, 2, 0, 2, 3].map(|k| base + k);
                // Counter-clockwise seen from outside: the normal is (u × v) per side.
                if u.cross(v).dot(n) > 0.0 {
                    indices.extend(tri);
                } else {
                    indices.extend([tri[0], tri[2], tri[1], tri[3], tri[5], tri[4]]);
                }
            }
        }
        (positions, indices)
    }

    fn normal(p: &[Vec3], i: &[u32], face: u32) -> Vec3 {
        let t = &i[face as usize * 3..face as usize * 3 + 3];
        let (a, b, c) = (p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]);
        (b - a).cross(c - a)
    }

    #[test]
    fn a_cube_of_24_vertices_is_closed_with_18_edges_each_wound_both_ways() {
        let (p, i) = cube();
        let e = mesh_edges(&p, &i);
        assert!(e.closed, "{e:?}");
        assert_eq!(e.edges.len(), 18, "12 box edges and 6 diagonals");
        assert_eq!((e.open_edges, e.non_manifold_edges), (0, 0));
        for edge in &e.edges {
            assert_ne!(edge.opposite, NO_FACE);
            assert!(p[edge.a as usize].distance(p[edge.b as usize]) > 0.0);
        }
    }

    #[test]
    fn a_lit_cube_extrudes_exactly_its_silhouette_loop() {
        let (p, i) = cube();
        let e = mesh_edges(&p, &i);
        // Light from above and a little from +x and +z: the lit sides are +y, +x and +z.
        let to_light = Vec3::new(0.3, 1.0, 0.2);
        let sign = |f: u32| face_sign(normal(&p, &i, f).dot(to_light) > 0.0, e.closed);
        let mut silhouette: Vec<(Vec3, Vec3, i32)> = e
            .edges
            .iter()
            .filter_map(|edge| {
                let m = multiplicity(sign(edge.face), Some(sign(edge.opposite)));
                (m != 0).then(|| (p[edge.a as usize], p[edge.b as usize], m))
            })
            .collect();
        // Six edges between a lit and an unlit side, each once.
        assert_eq!(silhouette.len(), 6, "{silhouette:?}");
        assert!(silhouette.iter().all(|s| s.2.abs() == 1));
        // They form one loop: every corner is the start of one and the end of one (as
        // extruded: reversed where the multiplicity is negative).
        for s in &mut silhouette {
            if s.2 < 0 {
                (s.0, s.1) = (s.1, s.0);
            }
        }
        for s in &silhouette {
            assert_eq!(silhouette.iter().filter(|t| t.0 == s.1).count(), 1);
        }
        // Each lies between a lit side (+x, +y or +z) and an unlit one (-x, -y or -z).
        for s in &silhouette {
            let mid = ((s.0 + s.1) * 0.5).to_array();
            assert_eq!(
                mid.iter().filter(|c| (**c - 0.5).abs() < 1e-6).count(),
                1,
                "{s:?}"
            );
            assert_eq!(
                mid.iter().filter(|c| (**c + 0.5).abs() < 1e-6).count(),
                1,
                "{s:?}"
            );
        }
    }

    #[test]
    fn a_cube_is_convex_and_two_cubes_in_one_mesh_or_an_open_quad_are_not() {
        let (p, i) = cube();
        assert!(mesh_edges(&p, &i).convex);
        // A second cube beside the first, in the same mesh: each part is convex, the mesh is
        // not (the first's face towards it has the second's corners in front of it).
        let mut two = p.clone();
        two.extend(p.iter().map(|q| *q + Vec3::new(3.0, 0.0, 0.0)));
        let n = p.len() as u32;
        let mut both = i.clone();
        both.extend(i.iter().map(|k| k + n));
        let e = mesh_edges(&two, &both);
        assert!(e.closed && !e.convex, "{e:?}");
        let flat = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z];
        assert!(!mesh_edges(&flat, &[0, 2, 1, 0, 3, 2]).convex);
    }

    #[test]
    fn an_open_quad_and_a_fin_are_not_closed_and_keep_every_triangle() {
        // A quad of two triangles: four open edges and one shared diagonal.
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let quad = mesh_edges(&p, &[0, 2, 1, 0, 3, 2]);
        assert!(!quad.closed);
        assert_eq!((quad.edges.len(), quad.open_edges), (5, 4));
        // Lit from below (its back): both triangles cast, as -1; the shared diagonal cancels
        // and the border is extruded once.
        let sign = face_sign(false, quad.closed);
        assert_eq!(sign, -1);
        for edge in &quad.edges {
            let opposite = (edge.opposite != NO_FACE).then_some(sign);
            let m = multiplicity(sign, opposite);
            assert_eq!(m, if opposite.is_some() { 0 } else { -1 }, "{edge:?}");
        }
        // Three triangles on one edge (a fin): the edge is kept once per triangle.
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            Vec3::new(0.5, -1.0, 0.5),
        ];
        let fin = mesh_edges(&p, &[0, 1, 2, 1, 0, 3, 0, 1, 4]);
        assert!(!fin.closed);
        assert_eq!(fin.non_manifold_edges, 1);
        let on_base = fin
            .edges
            .iter()
            .filter(|e| (e.a.min(e.b), e.a.max(e.b)) == (0, 1))
            .count();
        assert_eq!(on_base, 3);
        assert!(
            fin.edges
                .iter()
                .all(|e| e.opposite == NO_FACE || e.a.max(e.b) > 1)
        );
    }

    #[test]
    fn degenerate_triangles_are_left_out_and_open_the_mesh() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::X, Vec3::Y];
        let e = mesh_edges(&p, &[0, 1, 2, 0, 1, 3]);
        assert_eq!(e.degenerate_triangles, 1);
        assert!(!e.closed);
        assert_eq!(e.edges.len(), 3);
        assert!(e.edges.iter().all(|e| e.face == 1));
    }
}
