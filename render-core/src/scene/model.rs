//! The scene model: meshes shared between instances, instances with a name, a transform, a world
//! box and flags, and one directional sun. Only what a scene needs.

use glam::{Mat4, Vec3};
use serde::Serialize;

use super::bvh::Bvh;
use super::motion::Motion;
use crate::geom::Aabb;

/// Index of a mesh in [`Scene::meshes`].
pub type MeshId = u32;

/// Triangle geometry in its own local space, shared by every instance that refers to it.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub name: String,
    pub positions: Vec<Vec3>,
    /// One unit normal per position.
    pub normals: Vec<Vec3>,
    /// Triangle list, three indices per triangle.
    pub indices: Vec<u32>,
    pub aabb_in_local: Aabb,
}

impl Mesh {
    /// A mesh from positions and indices; normals are computed when `normals` is `None`.
    pub fn new(
        name: impl Into<String>,
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        indices: Vec<u32>,
    ) -> Self {
        let normals = normals.unwrap_or_else(|| compute_vertex_normals(&positions, &indices));
        let aabb_in_local = Aabb::from_points(positions.iter().copied());
        Self {
            name: name.into(),
            positions,
            normals,
            indices,
            aabb_in_local,
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// Area-weighted vertex normals; a vertex touching only degenerate triangles gets +Y.
pub fn compute_vertex_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| i as usize);
        if a >= positions.len() || b >= positions.len() || c >= positions.len() {
            continue;
        }
        let face = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        for i in [a, b, c] {
            normals[i] += face;
        }
    }
    normals
        .iter()
        .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
        .collect()
}

/// Whether an instance can move between frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mobility {
    Static,
    Dynamic,
}

/// One placed copy of a mesh.
#[derive(Clone, Debug)]
pub struct Instance {
    /// The glTF node name (with a `#chunk` suffix for split objects), or a generated name.
    pub name: String,
    pub mesh: MeshId,
    pub world_from_local: Mat4,
    pub aabb_in_world: Aabb,
    /// Linear RGBA.
    pub base_color: [f32; 4],
    pub casts_shadow: bool,
    pub receives_shadow: bool,
    pub mobility: Mobility,
}

impl Instance {
    /// An instance that casts and receives shadows; its world box is computed from the mesh.
    pub fn new(
        name: impl Into<String>,
        mesh: MeshId,
        mesh_data: &Mesh,
        world_from_local: Mat4,
    ) -> Self {
        Self {
            name: name.into(),
            mesh,
            world_from_local,
            aabb_in_world: mesh_data.aabb_in_local.transformed(&world_from_local),
            base_color: [0.8, 0.8, 0.8, 1.0],
            casts_shadow: true,
            receives_shadow: true,
            mobility: Mobility::Static,
        }
    }

    #[must_use]
    pub fn with_color(mut self, base_color: [f32; 4]) -> Self {
        self.base_color = base_color;
        self
    }

    #[must_use]
    pub fn with_mobility(mut self, mobility: Mobility) -> Self {
        self.mobility = mobility;
        self
    }
}

/// A point or spot light of the scene (glTF `KHR_lights_punctual`): where it is and how it
/// shines, in metres, candela and linear RGB. The frame does not shade or shadow with these
/// yet; the scene keeps them so the techniques that do can.
#[derive(Clone, Debug, PartialEq)]
pub struct PunctualLight {
    pub name: String,
    pub position: Vec3,
    pub kind: LightKind,
    pub color: [f32; 3],
    /// Candela.
    pub intensity: f32,
    /// Where its light ends, metres (`None`: nowhere, falling off with distance squared).
    pub range: Option<f32>,
}

/// How a punctual light shines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// In every direction.
    Point,
    /// Along `direction` (unit), full inside `inner_cone_rad` and fading to none at
    /// `outer_cone_rad` from it.
    Spot {
        direction: Vec3,
        inner_cone_rad: f32,
        outer_cone_rad: f32,
    },
}

/// The sun: a directional light. `direction_to_sun` points from the scene towards the sun.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sun {
    pub direction_to_sun: Vec3,
}

impl Sun {
    /// The sun's illuminance, lux: the shading's unit (clear-sky direct sun), which point
    /// lights' intensities over distance squared are measured against.
    pub const ILLUMINANCE_LX: f32 = 100_000.0;

    /// Azimuth is measured in the XZ plane from +X towards +Z, elevation up from the horizon.
    pub fn from_azimuth_elevation_deg(azimuth_deg: f32, elevation_deg: f32) -> Self {
        let (az, el) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
        Self {
            direction_to_sun: Vec3::new(el.cos() * az.cos(), el.sin(), el.cos() * az.sin()),
        }
    }

    /// A sun pointing along `direction_to_sun`, or straight overhead for a zero vector.
    pub fn from_direction(direction_to_sun: Vec3) -> Self {
        Self {
            direction_to_sun: direction_to_sun.try_normalize().unwrap_or(Vec3::Y),
        }
    }

    pub fn azimuth_elevation_deg(&self) -> (f32, f32) {
        let d = self.direction_to_sun;
        let elevation = d.y.clamp(-1.0, 1.0).asin().to_degrees();
        let azimuth = d.z.atan2(d.x).to_degrees();
        (azimuth.rem_euclid(360.0), elevation)
    }
}

/// A point light that casts a frame's shadows in place of the sun (`--light point` or
/// `--light spot`): where it is, how bright, candela, and a spot's cone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointShadow {
    pub position: Vec3,
    pub intensity_cd: f32,
    /// A spot light's cone (`None`: it shines every way).
    pub cone: Option<SpotCone>,
}

/// A spot light's cone: along `direction` (unit), full within `inner_rad` of it and fading to
/// none at `outer_rad` (glTF's `innerConeAngle` and `outerConeAngle`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotCone {
    pub direction: Vec3,
    pub inner_rad: f32,
    pub outer_rad: f32,
}

impl SpotCone {
    /// Whether the light reaches along `offset` from the light: strictly inside the outer cone.
    pub fn holds(&self, offset: Vec3) -> bool {
        offset.normalize_or_zero().dot(self.direction) > self.outer_rad.cos()
    }
}

impl PointShadow {
    /// A light at `position` of `intensity_cd` shining every way.
    pub fn omni(position: Vec3, intensity_cd: f32) -> Self {
        Self {
            position,
            intensity_cd,
            cone: None,
        }
    }

    /// The `index`th point or spot light of `scene` (a spot keeps its cone).
    pub fn of_scene(scene: &Scene, index: usize) -> Option<Self> {
        scene.lights.get(index).map(Self::of_light)
    }

    /// The `index`th spot light of `scene`.
    pub fn spot_of_scene(scene: &Scene, index: usize) -> Option<Self> {
        scene.spot_lights().map(Self::of_light).nth(index)
    }

    fn of_light(light: &PunctualLight) -> Self {
        Self {
            position: light.position,
            intensity_cd: light.intensity,
            cone: match light.kind {
                LightKind::Point => None,
                LightKind::Spot {
                    direction,
                    inner_cone_rad,
                    outer_cone_rad,
                } => Some(SpotCone {
                    direction: direction.normalize_or(Vec3::NEG_Y),
                    inner_rad: inner_cone_rad.min(outer_cone_rad),
                    outer_rad: outer_cone_rad,
                }),
            },
        }
    }

    /// Where its shadows come from.
    pub fn shadow_light(&self) -> ShadowLight {
        match self.cone {
            None => ShadowLight::Point(self.position),
            Some(cone) => ShadowLight::Spot(self.position, cone),
        }
    }
}

/// Where the shadows a frame casts come from: a direction towards the sun, or a point (a spot
/// light's, within its cone).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShadowLight {
    Sun(Vec3),
    Point(Vec3),
    Spot(Vec3, SpotCone),
}

impl ShadowLight {
    /// From `p` towards the light: a unit direction, and how far along it the light is.
    pub fn towards(&self, p: Vec3) -> (Vec3, f32) {
        match *self {
            Self::Sun(direction) => (direction.normalize_or(Vec3::Y), f32::INFINITY),
            Self::Point(at) | Self::Spot(at, _) => {
                let d = at - p;
                let distance = d.length();
                (d / distance.max(1e-12), distance)
            }
        }
    }

    /// Whether the light shines on `p` at all: everywhere but outside a spot's cone.
    pub fn reaches(&self, p: Vec3) -> bool {
        match *self {
            Self::Sun(_) | Self::Point(_) => true,
            Self::Spot(at, cone) => cone.holds(p - at),
        }
    }
}

impl From<Vec3> for ShadowLight {
    /// A direction towards the sun.
    fn from(direction_to_sun: Vec3) -> Self {
        Self::Sun(direction_to_sun)
    }
}

impl Default for Sun {
    fn default() -> Self {
        Self::from_azimuth_elevation_deg(35.0, 45.0)
    }
}

/// Meshes, their instances, the sun, and derived data kept up to date: bounds and the BVH.
#[derive(Clone, Debug)]
pub struct Scene {
    /// `builtin:NAME` or the file path it came from.
    pub name: String,
    pub meshes: Vec<Mesh>,
    pub instances: Vec<Instance>,
    pub sun: Sun,
    /// Scripted motion of dynamic instances (cars on their lanes); see [`Scene::animate`].
    pub motions: Vec<Motion>,
    /// Point and spot lights, as the file has them.
    pub lights: Vec<PunctualLight>,
    bounds: Aabb,
    bvh: Bvh,
}

impl Scene {
    /// Its spot lights, in order.
    pub fn spot_lights(&self) -> impl Iterator<Item = &PunctualLight> {
        self.lights
            .iter()
            .filter(|l| matches!(l.kind, LightKind::Spot { .. }))
    }

    pub fn new(
        name: impl Into<String>,
        meshes: Vec<Mesh>,
        instances: Vec<Instance>,
        sun: Sun,
    ) -> Self {
        let boxes: Vec<Aabb> = instances.iter().map(|i| i.aabb_in_world).collect();
        let bounds = boxes.iter().fold(Aabb::EMPTY, |acc, b| acc.union(*b));
        let bvh = Bvh::build(&boxes);
        Self {
            name: name.into(),
            meshes,
            instances,
            sun,
            motions: Vec::new(),
            lights: Vec::new(),
            bounds,
            bvh,
        }
    }

    /// The scene moved by `offset` (a hard case: far from the origin), its lights too; what
    /// moved stands still there.
    #[must_use]
    pub fn moved_by(&self, offset: Vec3) -> Self {
        let to = Mat4::from_translation(offset);
        let instances = self
            .instances
            .iter()
            .map(|i| Instance {
                world_from_local: to * i.world_from_local,
                aabb_in_world: self.meshes[i.mesh as usize]
                    .aabb_in_local
                    .transformed(&(to * i.world_from_local)),
                ..i.clone()
            })
            .collect();
        let mut lights = self.lights.clone();
        for light in &mut lights {
            light.position += offset;
        }
        Self {
            lights,
            ..Self::new(self.name.clone(), self.meshes.clone(), instances, self.sun)
        }
    }

    /// The scene with every instance `copies` times in its place (Rákos's Figure 19.7: the
    /// scene instanced four times): the same shadows from `copies` times the geometry. The
    /// copies are named `NAME#copy K` and stand still; the lights and the originals' motion
    /// stay.
    #[must_use]
    pub fn with_copies(self, copies: u32) -> Self {
        if copies <= 1 {
            return self;
        }
        let mut instances = self.instances.clone();
        for k in 1..copies {
            instances.extend(self.instances.iter().map(|i| Instance {
                name: format!("{}#copy {k}", i.name),
                ..i.clone()
            }));
        }
        let mut scene = Self::new(self.name, self.meshes, instances, self.sun);
        scene.motions = self.motions;
        scene.lights = self.lights;
        scene
    }

    /// The box around every instance, in world space.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    pub fn mesh_of(&self, instance: &Instance) -> &Mesh {
        &self.meshes[instance.mesh as usize]
    }

    /// Triangles over all instances (a mesh instanced twice counts twice).
    pub fn triangle_count(&self) -> usize {
        self.instances
            .iter()
            .map(|i| self.mesh_of(i).triangle_count())
            .sum()
    }

    pub fn caster_count(&self) -> usize {
        self.instances.iter().filter(|i| i.casts_shadow).count()
    }

    /// Moves a dynamic instance. Call [`Scene::refit`] once after moving a batch.
    pub fn set_world_from_local(&mut self, instance: usize, world_from_local: Mat4) {
        let aabb = self.meshes[self.instances[instance].mesh as usize]
            .aabb_in_local
            .transformed(&world_from_local);
        let inst = &mut self.instances[instance];
        inst.world_from_local = world_from_local;
        inst.aabb_in_world = aabb;
    }

    /// Poses every instance that has a motion for `time_s` seconds and refits the BVH.
    /// Returns the instances that moved.
    pub fn animate(&mut self, time_s: f64) -> Vec<u32> {
        let motions = std::mem::take(&mut self.motions);
        for m in &motions {
            self.set_world_from_local(m.instance as usize, m.world_from_local(time_s));
        }
        let moved = motions.iter().map(|m| m.instance).collect();
        self.motions = motions;
        self.refit();
        moved
    }

    /// Refits the BVH and bounds to the instances' current world boxes.
    pub fn refit(&mut self) {
        let boxes: Vec<Aabb> = self.instances.iter().map(|i| i.aabb_in_world).collect();
        self.bounds = boxes.iter().fold(Aabb::EMPTY, |acc, b| acc.union(*b));
        self.bvh.refit(&boxes);
    }
}

/// A short summary for panels and reports.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct SceneFacts {
    pub name: String,
    pub objects: usize,
    pub meshes: usize,
    pub triangles: usize,
    pub casters: usize,
    /// Point and spot lights.
    pub lights: usize,
    /// The first of them, which `--light point` casts shadows from (a spot in its cone).
    #[serde(skip)]
    pub point_light: Option<PointShadow>,
    pub bounds_min_m: [f32; 3],
    pub bounds_max_m: [f32; 3],
}

impl From<&Scene> for SceneFacts {
    fn from(scene: &Scene) -> Self {
        Self {
            name: scene.name.clone(),
            objects: scene.instances.len(),
            meshes: scene.meshes.len(),
            triangles: scene.triangle_count(),
            casters: scene.caster_count(),
            lights: scene.lights.len(),
            point_light: PointShadow::of_scene(scene, 0),
            bounds_min_m: scene.bounds.min.to_array(),
            bounds_max_m: scene.bounds.max.to_array(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sun_round_trips_azimuth_elevation() {
        let sun = Sun::from_azimuth_elevation_deg(123.0, 17.0);
        let (az, el) = sun.azimuth_elevation_deg();
        assert!((az - 123.0).abs() < 1e-3 && (el - 17.0).abs() < 1e-3);
        assert!((sun.direction_to_sun.length() - 1.0).abs() < 1e-6);
        assert_eq!(Sun::from_direction(Vec3::ZERO).direction_to_sun, Vec3::Y);
    }

    #[test]
    fn normals_of_degenerate_triangles_are_finite() {
        let positions = vec![Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, Vec3::X];
        let normals = compute_vertex_normals(&positions, &[0, 1, 2]);
        assert!(
            normals
                .iter()
                .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-6)
        );
    }

    #[test]
    fn copies_stand_in_their_originals_place_with_the_lights_kept() {
        let hall = crate::scene::load_builtin("hall", 3).expect("the hall");
        let (objects, triangles) = (hall.instances.len(), hall.triangle_count());
        let lights = hall.lights.clone();
        let bounds = hall.bounds();
        let four = hall.with_copies(4);
        assert_eq!(four.instances.len(), 4 * objects);
        assert_eq!(four.triangle_count(), 4 * triangles);
        assert_eq!(four.lights, lights);
        assert_eq!(four.bounds(), bounds);
        let copy = &four.instances[2 * objects + 5];
        assert_eq!(copy.name, format!("{}#copy 2", four.instances[5].name));
        assert_eq!(copy.world_from_local, four.instances[5].world_from_local);
    }
}
