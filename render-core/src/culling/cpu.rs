//! The CPU methods, `none` and `vfc`, choosing one shadow view's casters through the scene's
//! BVH. Long-lived state (the scene's casters, scratch lists); the choice is made per frame.

use super::{CasterOutcome, Method, Stage, StageKind};
use crate::geom::{Frustum, LightFrustum};
use crate::scene::Scene;

/// One view's casters this frame, per method, and each object's outcome.
#[derive(Debug, Default)]
pub struct CasterSelection {
    /// The scene `all` belongs to.
    scene_id: u64,
    /// Every caster of the scene, sorted.
    all: Vec<u32>,
    /// The casters the method draws, sorted.
    chosen: Vec<u32>,
    outcomes: Vec<CasterOutcome>,
    /// Casters left out on request (what-if experiments); sorted.
    excluded: Vec<u32>,
    scratch: Vec<u32>,
}

impl CasterSelection {
    /// Chooses this frame's casters for `method` and returns the culling stages in order, each
    /// with the casters left after it. `scene_id` tells scenes apart (`SceneGpu::id`).
    pub fn select(
        &mut self,
        scene: &Scene,
        scene_id: u64,
        method: Method,
        light: &LightFrustum,
    ) -> Vec<Stage> {
        if self.scene_id != scene_id || self.all.is_empty() {
            self.scene_id = scene_id;
            self.all = (0..scene.instances.len() as u32)
                .filter(|&i| scene.instances[i as usize].casts_shadow)
                .collect();
        }
        let mut stages = vec![Stage::new("scene casters", self.all.len() as u32)];
        self.chosen.clear();
        match method {
            Method::None => self.chosen.extend_from_slice(&self.all),
            Method::Vfc => {
                let light_frustum = Frustum::from_clip_from_world(&light.light_clip_from_world);
                self.scratch.clear();
                scene.bvh().query_frustum(&light_frustum, &mut self.scratch);
                self.chosen.extend(
                    self.scratch
                        .iter()
                        .copied()
                        .filter(|&i| scene.instances[i as usize].casts_shadow),
                );
                self.chosen.sort_unstable();
                stages.push(Stage::new(
                    StageKind::LightFrustum.name(),
                    self.chosen.len() as u32,
                ));
            }
            // The GPU methods choose later in the frame (`GpuCulling`); here only the scene's
            // casters are kept.
            _ => {}
        }
        if !self.excluded.is_empty() {
            let excluded = &self.excluded;
            self.chosen.retain(|i| excluded.binary_search(i).is_err());
        }
        self.record_outcomes(scene.instances.len(), stages.len());
        stages
    }

    /// Per instance: rendered, culled at a stage, excluded, or not a caster. Each method so far
    /// culls only at its last stage.
    fn record_outcomes(&mut self, instance_count: usize, stage_count: usize) {
        self.outcomes.clear();
        self.outcomes
            .resize(instance_count, CasterOutcome::NotACaster);
        let last_stage = stage_count.saturating_sub(1);
        for &i in &self.all {
            self.outcomes[i as usize] = CasterOutcome::Culled { stage: last_stage };
        }
        for &i in &self.excluded {
            if let Some(o) = self.outcomes.get_mut(i as usize) {
                *o = CasterOutcome::Excluded;
            }
        }
        for &i in &self.chosen {
            self.outcomes[i as usize] = CasterOutcome::Rendered;
        }
    }

    /// Casters left out on request, sorted.
    pub fn excluded(&self) -> &[u32] {
        &self.excluded
    }

    /// Leaves these instances out of the chosen casters from the next frame on.
    pub fn exclude(&mut self, instances: &[u32]) {
        self.excluded = instances.to_vec();
        self.excluded.sort_unstable();
    }

    /// Every caster of the scene, sorted.
    pub fn all(&self) -> &[u32] {
        &self.all
    }

    /// The casters the method draws this frame, sorted.
    pub fn chosen(&self) -> &[u32] {
        &self.chosen
    }

    /// What happened to each instance this frame.
    pub fn outcomes(&self) -> &[CasterOutcome] {
        &self.outcomes
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec3};

    use super::*;
    use crate::geom::{Aabb, Camera, fit_directional_light};
    use crate::scene::{Instance, Mesh, Sun};

    /// Boxes along the x axis; the one at index 2 casts no shadow.
    fn row_of_boxes() -> Scene {
        let cube = Mesh::new(
            "cube",
            Aabb::new(Vec3::splat(-1.0), Vec3::ONE).corners().to_vec(),
            None,
            vec![0, 1, 2, 1, 3, 2],
        );
        let instances = (0..6)
            .map(|k| {
                let mut inst = Instance::new(
                    format!("box_{k}"),
                    0,
                    &cube,
                    Mat4::from_translation(Vec3::new(k as f32 * 100.0, 1.0, 0.0)),
                );
                inst.casts_shadow = k != 2;
                inst
            })
            .collect();
        Scene::new("test", vec![cube], instances, Sun::from_direction(Vec3::Y))
    }

    #[test]
    fn none_chooses_every_caster_and_vfc_those_in_the_light_frustum() {
        let scene = row_of_boxes();
        // A camera whose view spans x from about -10 to 210 m: boxes 0 to 2 (2 casts no shadow).
        let camera = Camera::look_at(
            Vec3::new(100.0, 60.0, 150.0),
            Vec3::new(100.0, 0.0, 0.0),
            1.2,
            0.1,
            400.0,
        );
        let light = fit_directional_light(
            &camera,
            1.0,
            scene.sun.direction_to_sun,
            &scene.bounds(),
            1024,
        );
        let mut selection = CasterSelection::default();
        let stages = selection.select(&scene, 1, Method::None, &light);
        assert_eq!(selection.chosen(), &[0, 1, 3, 4, 5]);
        assert_eq!(stages.len(), 1);
        assert_eq!(selection.outcomes()[2], CasterOutcome::NotACaster);

        let stages = selection.select(&scene, 1, Method::Vfc, &light);
        assert_eq!(stages[1].name, "light frustum");
        assert_eq!(stages[1].remaining as usize, selection.chosen().len());
        assert!(selection.chosen().contains(&0) && selection.chosen().contains(&1));
        assert!(
            !selection.chosen().contains(&5),
            "the far box is outside the light frustum"
        );
        assert_eq!(selection.outcomes()[5], CasterOutcome::Culled { stage: 1 });
        assert_eq!(selection.outcomes()[5].describe(&stages), "light frustum");
    }

    #[test]
    fn excluded_casters_are_left_out_and_reported() {
        let scene = row_of_boxes();
        let camera = Camera::look_at(
            Vec3::new(250.0, 300.0, 400.0),
            Vec3::new(250.0, 0.0, 0.0),
            1.2,
            0.1,
            2000.0,
        );
        let light = fit_directional_light(
            &camera,
            1.0,
            scene.sun.direction_to_sun,
            &scene.bounds(),
            1024,
        );
        let mut selection = CasterSelection::default();
        selection.exclude(&[4, 0]);
        selection.select(&scene, 7, Method::None, &light);
        assert_eq!(selection.chosen(), &[1, 3, 5]);
        assert_eq!(selection.outcomes()[0], CasterOutcome::Excluded);
        assert_eq!(selection.outcomes()[1], CasterOutcome::Rendered);
        assert_eq!(selection.all(), &[0, 1, 3, 4, 5]);
    }
}
