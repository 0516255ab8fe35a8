//! The exact shadow: the truth every shadow technique is measured against.
//!
//! For each pixel, a ray from the camera through the pixel's centre finds the surface the
//! pixel shows (the first front face, as the rasteriser culls back faces), and a ray from
//! that point towards the sun says whether any caster blocks it. Both run on the CPU through
//! a BVH of the scene's triangles (`rays.rs`, `obvhs`), never from the depth buffer. The
//! technique's light is then read at the same points on the GPU (`at_points.rs`) and compared:
//! a pixel is shadowed where less than half the light reaches it.
//!
//! Counted pixels are visible receivers that face the light (and lie inside a spot light's
//! cone); a pixel that faces away, or that the cone leaves out, is dark whatever the shadow
//! says. A view's truth is cached by its camera, size, sun and the
//! instances' poses, and computed only when measuring.

#[cfg(test)]
mod arbiter;
mod at_points;
mod rays;
#[cfg(test)]
mod tests;

use std::collections::VecDeque;

use glam::{DVec3, Vec3};
use serde::Serialize;

#[cfg(test)]
pub(crate) use at_points::shader_source;
pub use at_points::{FrameGroups, LightAtPoints, PendingLight, SurfacePoint};
pub use rays::{SceneRays, SurfaceHit, offset_from_surface};

use crate::geom::Camera;
use crate::metrics::ShadowError;
use crate::scene::{Scene, ShadowLight};

/// Below this fraction of light a point is shadowed.
pub const SHADOWED_BELOW: f32 = 0.5;

/// A surface whose normal's cosine with the direction to the light is at most this grazes
/// the light and is not counted (0.057°: it receives a thousandth of the light). Its shadow
/// does not show, and no technique can resolve it: under a sun at the zenith, a wall faces
/// the light by the rounding of the sun's direction (4e-8), and a shadow volume's side runs
/// along it a fraction of a micrometre away, a coin toss for any rasteriser.
pub const GRAZING: f32 = 1e-3;

/// What the truth says of one pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PixelTruth {
    /// No surface within the camera's near and far planes.
    Sky,
    /// An object that does not receive shadows.
    NotReceiver,
    /// The surface faces away from the light, or grazes it (it faces the light by no more
    /// than [`GRAZING`]): not counted.
    FacesAway,
    /// A spot light's cone does not reach the surface: dark whatever the shadow; not counted.
    OutsideCone,
    Lit,
    Shadowed,
}

/// Everything that decides a view's truth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewKey {
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
    pub light: ShadowLight,
    /// [`SceneRays::version`]: the instances' poses.
    pub poses: u64,
}

/// One view's truth.
#[derive(Clone, Debug)]
pub struct ExactShadow {
    pub key: ViewKey,
    /// Per pixel, row by row from the top.
    pub pixels: Vec<PixelTruth>,
    /// The counted pixels' surface points, in pixel order.
    pub points: Vec<SurfacePoint>,
    /// Each counted point's pixel index.
    pub point_pixels: Vec<u32>,
    /// Where each counted point's ray towards the light starts ([`SurfaceHit::leaving`]).
    pub leaving: Vec<DVec3>,
    /// Whether each counted point's pixel lies on an edge of the exact picture, where
    /// sampling decides what a pixel shows (see [`ExactShadow::cast`] for the rule).
    pub on_edge: Vec<bool>,
}

impl ExactShadow {
    /// Casts a ray through every pixel centre of `key`'s view and one towards the light (the
    /// sun, or up to a point light) from each surface it finds, on every core.
    ///
    /// **The edge rule.** A counted pixel is on an edge when one of its eight neighbours has
    /// another truth (sky, another kind of surface, the other side of a shadow's boundary: the
    /// exact shadow changes within a pixel of its centre) or shows a surface its own does
    /// not continue (the visible surface jumps in depth: [`surfaces_jump`]). There, where the
    /// boundary falls inside the pixel decides its colour, and a rasteriser and a ray through
    /// the centre may disagree by a rounding: such error is sampling, not a wrong shadow.
    /// Nothing else excuses error: not where one object meets another or where a mesh was
    /// cut into chunks for culling (the rule never asks which object a pixel shows), and not
    /// a speckled error inside a uniformly lit or shadowed face.
    pub fn cast(rays: &SceneRays, key: ViewKey) -> Self {
        let (width, height) = (key.width.max(1), key.height.max(1));
        let view = PixelRays::of(&key);
        let pixel = |x: u32, y: u32| view.truth_at(rays, &key, (x as f32 + 0.5, y as f32 + 0.5));
        let rows = rows_in_parallel(height, |y| {
            (0..width).map(|x| pixel(x, y)).collect::<Vec<_>>()
        });
        let mut out = Self {
            key,
            pixels: Vec::with_capacity((width * height) as usize),
            points: Vec::new(),
            point_pixels: Vec::new(),
            leaving: Vec::new(),
            on_edge: Vec::new(),
        };
        let mut surfaces = Vec::with_capacity((width * height) as usize);
        for (i, sample) in (0..).zip(rows.into_iter().flatten()) {
            out.pixels.push(sample.truth);
            surfaces.push(sample.hit.as_ref().map(surface_of));
            if let (Some(p), Some(hit)) = (sample.point, sample.hit) {
                out.points.push(p);
                out.point_pixels.push(i);
                out.leaving.push(hit.leaving);
            }
        }
        out.on_edge = out
            .point_pixels
            .iter()
            .map(|&i| {
                let (x, y) = (i % width, i / width);
                let own = i as usize;
                neighbours(x, y, width, height).any(|n| {
                    out.pixels[n] != out.pixels[own]
                        || match (surfaces[own], surfaces[n]) {
                            (Some(a), Some(b)) => surfaces_jump(view.eye, view.forward, a, b),
                            _ => true,
                        }
                })
            })
            .collect();
        out
    }

    /// Memory it holds.
    pub fn bytes(&self) -> usize {
        self.pixels.len() * std::mem::size_of::<PixelTruth>()
            + self.points.len()
                * (std::mem::size_of::<SurfacePoint>() + std::mem::size_of::<DVec3>() + 5)
    }

    /// Whether counted point `i` is shadowed in truth.
    pub fn shadowed(&self, i: usize) -> bool {
        self.pixels[self.point_pixels[i] as usize] == PixelTruth::Shadowed
    }

    /// Counted pixels whose shadow in `light` (the light at each point, as
    /// [`LightAtPoints::evaluate`] returns it) differs from the truth.
    pub fn error_of(&self, light: &[f32]) -> ShadowError {
        let mut error = ShadowError {
            visible_px: self.points.len() as u32,
            ..ShadowError::default()
        };
        let mut off_edges = 0;
        for (i, &l) in light.iter().enumerate().take(self.points.len()) {
            match (self.shadowed(i), l < SHADOWED_BELOW) {
                (true, false) => error.missing_shadow_px += 1,
                (false, true) => error.extra_shadow_px += 1,
                _ => continue,
            }
            off_edges += u32::from(!self.on_edge[i]);
        }
        error.off_edge_px = Some(off_edges);
        error
    }

    /// As [`ExactShadow::error_of`], and a differing pixel whose neighbours all agree with it
    /// is on an edge too where the truth changes inside it: at one of a grid of
    /// `SUBPIXELS` x `SUBPIXELS` points over the pixel, its sides included (a gap between two
    /// shadows, or a shadow, narrower than a pixel: the corridor's struts leave lit specks an
    /// eighth of a pixel wide), or where an occluding contour crosses its centre
    /// ([`PixelRays::contour_at`]: a silhouette edge crossing the pixel centre, where the
    /// rasteriser's rounding decides). `rays` are the scene's as the view was cast.
    pub fn error_within(&self, rays: &SceneRays, light: &[f32]) -> ShadowError {
        const SUBPIXELS: u32 = 9;
        let mut error = self.error_of(light);
        let view = PixelRays::of(&self.key);
        let width = self.key.width.max(1);
        let mut off_edges = 0;
        for (i, &l) in light.iter().enumerate().take(self.points.len()) {
            if self.on_edge[i] || self.shadowed(i) == (l < SHADOWED_BELOW) {
                continue;
            }
            let pixel = self.point_pixels[i];
            let own = self.pixels[pixel as usize];
            let (x, y) = ((pixel % width) as f32, (pixel / width) as f32);
            let contour = view.contour_at(rays, (x + 0.5, y + 0.5));
            let inside = contour
                || (0..SUBPIXELS * SUBPIXELS).any(|k| {
                    let at = |j: u32| j as f32 / (SUBPIXELS - 1) as f32;
                    let sample = view.truth_at(
                        rays,
                        &self.key,
                        (x + at(k % SUBPIXELS), y + at(k / SUBPIXELS)),
                    );
                    sample.truth != own
                });
            off_edges += u32::from(!inside);
        }
        error.off_edge_px = Some(off_edges);
        error
    }
}

/// How near a pixel centre an occluding contour counts as crossing it, pixels: rasterisers
/// snap vertices to 1/256 of a pixel, so an edge nearer than this may fall either side.
const CONTOUR_PX: f32 = 1.0 / 128.0;
/// Inverse view depths within this fraction of each other are the same surface's, whatever
/// the planes say (the points' own rounding).
const SAME_DEPTH: f32 = 1e-4;

/// Whether two visible surface points, `(position, normal)` each, seen from `eye` looking
/// along `forward`, lie on surfaces that do not continue each other (an occluding contour
/// passes between them). Which object each belongs to does not matter.
///
/// In a picture, the inverse view depth `w` of a plane is linear, so along the line from one
/// point's ray to the other's each surface's `w` runs straight. Where the two surfaces meet
/// (a crease, or a flat face cut in two), their lines cross between the rays and the gap
/// between them at either ray is at most the sum of the two lines' steps from one ray to the
/// other; where one surface passes in front of another, the gap is the jump in depth,
/// whatever the steps. So the test is resolution-aware: a crease seen almost edge-on from a
/// coarse picture is still a crease.
fn surfaces_jump(eye: Vec3, forward: Vec3, a: (Vec3, Vec3), b: (Vec3, Vec3)) -> bool {
    let (to_a, to_b) = (a.0 - eye, b.0 - eye);
    // `w` of the plane of `(p, n)`, whose own ray is `to_p`, along the ray `to_q`.
    let plane_w = |(_, n): (Vec3, Vec3), to_p: Vec3, to_q: Vec3| {
        n.dot(to_q) / (n.dot(to_p) * forward.dot(to_q))
    };
    let (a_at_a, b_at_b) = (1.0 / forward.dot(to_a), 1.0 / forward.dot(to_b));
    let (a_at_b, b_at_a) = (plane_w(a, to_a, to_b), plane_w(b, to_b, to_a));
    let steps = (a_at_b - a_at_a).abs() + (b_at_b - b_at_a).abs();
    let allowed = steps + SAME_DEPTH * a_at_a.max(b_at_b);
    let gaps = [(a_at_b - b_at_b).abs(), (b_at_a - a_at_a).abs()];
    !gaps.iter().all(|gap| gap.is_finite() && *gap <= allowed) || !allowed.is_finite()
}

/// The surface a camera ray met, for the edge rule: its point and normal.
fn surface_of(hit: &SurfaceHit) -> (Vec3, Vec3) {
    (hit.position, hit.normal)
}

/// The camera rays of a view: through any point of its picture, in pixels from the top left.
struct PixelRays {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half: f32,
    size: (f32, f32),
    depths: (f32, f32),
}

impl PixelRays {
    fn of(key: &ViewKey) -> Self {
        let camera = &key.camera;
        let (right, up) = camera.basis();
        Self {
            eye: camera.eye,
            forward: camera.forward.normalize_or(Vec3::NEG_Z),
            right,
            up,
            tan_half: (camera.fov_y_rad * 0.5).tan(),
            size: (key.width.max(1) as f32, key.height.max(1) as f32),
            depths: (camera.near_m, camera.far_m),
        }
    }

    /// The surface the ray through picture point `(x, y)` meets first.
    fn first_hit(&self, rays: &SceneRays, (x, y): (f32, f32)) -> Option<SurfaceHit> {
        let (width, height) = self.size;
        let ndc_x = 2.0 * x / width - 1.0;
        let ndc_y = 1.0 - 2.0 * y / height;
        // With `forward` of unit length, `t` along this direction is the view depth.
        let direction = self.forward
            + self.right * (ndc_x * self.tan_half * width / height)
            + self.up * (ndc_y * self.tan_half);
        rays.first_hit(self.eye, direction, self.depths.0, self.depths.1)
    }

    /// Whether what the picture shows changes within [`CONTOUR_PX`] of picture point `at`:
    /// the sky against a surface, or surfaces that do not continue each other
    /// ([`surfaces_jump`]). An occluding contour (a silhouette edge as the eye sees it) then
    /// crosses the point, and which side of it a pixel centre shows is the rasteriser's
    /// rounding of the edge, which two passes may round apart: a shadow volume's side, which
    /// starts on its caster's silhouette, counted at a centre where the caster's own face was
    /// not drawn.
    fn contour_at(&self, rays: &SceneRays, (x, y): (f32, f32)) -> bool {
        let surface_at = |at| self.first_hit(rays, at).map(|hit| surface_of(&hit));
        let centre = surface_at((x, y));
        [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)]
            .iter()
            .any(|&(dx, dy)| {
                match (
                    centre,
                    surface_at((x + dx * CONTOUR_PX, y + dy * CONTOUR_PX)),
                ) {
                    (Some(a), Some(b)) => surfaces_jump(self.eye, self.forward, a, b),
                    (None, None) => false,
                    _ => true,
                }
            })
    }

    /// The truth at picture point `(x, y)` (a pixel's centre is at half-integers), the
    /// surface point where it is counted, and the surface the ray met.
    fn truth_at(&self, rays: &SceneRays, key: &ViewKey, (x, y): (f32, f32)) -> Sample {
        let Some(hit) = self.first_hit(rays, (x, y)) else {
            return Sample::of(PixelTruth::Sky, None);
        };
        if !hit.receives_shadow {
            return Sample::of(PixelTruth::NotReceiver, Some(hit));
        }
        let (towards, distance) = key.light.towards(hit.position);
        if hit.normal.dot(towards) <= GRAZING {
            return Sample::of(PixelTruth::FacesAway, Some(hit));
        }
        if !key.light.reaches(hit.position) {
            return Sample::of(PixelTruth::OutsideCone, Some(hit));
        }
        let truth = if rays.blocked(hit.leaving, towards, (0.0, distance)) {
            PixelTruth::Shadowed
        } else {
            PixelTruth::Lit
        };
        Sample {
            truth,
            point: Some(SurfacePoint {
                position: hit.position.extend(1.0).to_array(),
                normal: hit.normal.extend(0.0).to_array(),
            }),
            hit: Some(hit),
        }
    }
}

/// What the truth says at one picture point.
struct Sample {
    truth: PixelTruth,
    /// Where a counted point's light is read.
    point: Option<SurfacePoint>,
    /// The surface the camera ray met first.
    hit: Option<SurfaceHit>,
}

impl Sample {
    /// A point that is not counted.
    fn of(truth: PixelTruth, hit: Option<SurfaceHit>) -> Self {
        Self {
            truth,
            point: None,
            hit,
        }
    }
}

/// The pixel indices of the up to eight neighbours of pixel (`x`, `y`) in a `width` x `height`
/// picture.
fn neighbours(x: u32, y: u32, width: u32, height: u32) -> impl Iterator<Item = usize> {
    let (x, y) = (i64::from(x), i64::from(y));
    (-1..=1)
        .flat_map(move |dy| (-1..=1).map(move |dx| (x + dx, y + dy)))
        .filter(move |&(nx, ny)| {
            (nx, ny) != (x, y)
                && (0..i64::from(width)).contains(&nx)
                && (0..i64::from(height)).contains(&ny)
        })
        .map(move |(nx, ny)| (ny * i64::from(width) + nx) as usize)
}

/// For each point, whether `camera` (its picture `aspect` = width / height) sees it: inside
/// its view frustum, and the first surface along the camera's ray to it (within a
/// ten-thousandth of its depth and a millimetre).
pub fn seen_from(
    rays: &SceneRays,
    camera: &Camera,
    aspect: f32,
    points: &[SurfacePoint],
) -> Vec<bool> {
    const CHUNK: usize = 1024;
    let clip_from_world = camera.clip_from_world(aspect);
    let forward = camera.forward.normalize_or(Vec3::NEG_Z);
    let sees = |p: &SurfacePoint| {
        let p = Vec3::from_slice(&p.position[..3]);
        let clip = clip_from_world * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        let depth = (p - camera.eye).dot(forward);
        if !(clip.w > 0.0 && ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && depth > camera.near_m)
            || depth > camera.far_m
        {
            return false;
        }
        // With the direction scaled so, `t` along it is the view depth, as the truth casts.
        let direction = (p - camera.eye) / depth;
        let tolerance = depth * 1e-4 + 1e-3;
        rays.first_hit(camera.eye, direction, camera.near_m, depth + tolerance)
            .is_some_and(|hit| hit.position.distance(p) <= tolerance)
    };
    let chunks = points.len().div_ceil(CHUNK) as u32;
    rows_in_parallel(chunks, |c| {
        let start = c as usize * CHUNK;
        points[start..(start + CHUNK).min(points.len())]
            .iter()
            .map(sees)
            .collect::<Vec<_>>()
    })
    .into_iter()
    .flatten()
    .collect()
}

/// `row(y)` for every `y` in `0..height` on every core; returned in order.
pub(crate) fn rows_in_parallel<T: Send>(height: u32, row: impl Fn(u32) -> T + Sync) -> Vec<T> {
    let threads = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    let next = std::sync::atomic::AtomicU32::new(0);
    let mut done: Vec<(u32, T)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let y = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        if y >= height {
                            break mine;
                        }
                        mine.push((y, row(y)));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("a ray-casting thread panicked"))
            .collect()
    });
    done.sort_unstable_by_key(|(y, _)| *y);
    done.into_iter().map(|(_, r)| r).collect()
}

/// The truth of the views a scene was measured from: its trees, built on first use, and the
/// most recent views' truths (a bench measures the same path with every method), up to a
/// memory budget.
pub struct TruthCache {
    rays: Option<SceneRays>,
    views: VecDeque<ExactShadow>,
    budget_bytes: usize,
    /// Views cast so far (not found in the cache).
    cast: u64,
}

impl Default for TruthCache {
    /// 512 MiB of views: 16 at 1280x720.
    fn default() -> Self {
        Self::new(512 << 20)
    }
}

impl TruthCache {
    /// A cache for one scene holding views up to `budget_bytes` (at least one view).
    pub fn new(budget_bytes: usize) -> Self {
        Self {
            rays: None,
            views: VecDeque::new(),
            budget_bytes,
            cast: 0,
        }
    }

    fn bytes(&self) -> usize {
        self.views.iter().map(ExactShadow::bytes).sum()
    }

    /// How many views were cast rather than found.
    pub fn views_cast(&self) -> u64 {
        self.cast
    }

    /// The scene's trees, following instances that moved.
    pub fn rays(&mut self, scene: &Scene) -> &SceneRays {
        match &mut self.rays {
            Some(rays) => rays.sync(&scene.instances),
            None => self.rays = Some(SceneRays::new(scene)),
        }
        self.rays.as_ref().expect("built above")
    }

    /// As [`TruthCache::exact`], with the trees it was cast through (for
    /// [`ExactShadow::error_within`]).
    pub fn exact_and_rays(
        &mut self,
        scene: &Scene,
        camera: &Camera,
        size: (u32, u32),
        light: impl Into<ShadowLight>,
    ) -> (&ExactShadow, &SceneRays) {
        self.exact(scene, camera, size, light);
        let rays = self.rays.as_ref().expect("built by exact");
        (self.views.back().expect("pushed by exact"), rays)
    }

    /// The truth of this view of `scene`, cast now or cached.
    pub fn exact(
        &mut self,
        scene: &Scene,
        camera: &Camera,
        (width, height): (u32, u32),
        light: impl Into<ShadowLight>,
    ) -> &ExactShadow {
        let poses = self.rays(scene).version;
        let key = ViewKey {
            camera: *camera,
            width,
            height,
            light: light.into(),
            poses,
        };
        if let Some(at) = self.views.iter().position(|v| v.key == key) {
            let view = self.views.remove(at).expect("found above");
            self.views.push_back(view);
        } else {
            let rays = self.rays.as_ref().expect("built above");
            let view = ExactShadow::cast(rays, key);
            self.cast += 1;
            while !self.views.is_empty() && self.bytes() + view.bytes() > self.budget_bytes {
                self.views.pop_front();
            }
            self.views.push_back(view);
        }
        self.views.back().expect("pushed above")
    }
}
