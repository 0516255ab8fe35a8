//! Editing the scene's punctual lights from the panel (the many-lights technique shadows
//! them): a spot light added at the camera, a light moved or removed. The scene changes at
//! once; the next frame renders their maps.

use render_core::scene::{LightKind, PunctualLight, SceneFacts, Sun};

use super::Running;

/// An added spot light: its cone and reach, and an intensity that gives a surface 10 m away a
/// tenth of the sun's illuminance.
const ADDED_OUTER_CONE_DEG: f32 = 30.0;
const ADDED_INNER_CONE_DEG: f32 = 24.0;
const ADDED_RANGE_M: f32 = 40.0;
const ADDED_INTENSITY_CD: f32 = Sun::ILLUMINANCE_LX / 10.0 * 100.0;

impl Running {
    /// A white spot light at the camera, shining where it looks.
    pub(super) fn add_spot_light(&mut self) {
        let camera = self.controller.camera;
        let name = format!("spot_added_{}", self.scene.lights.len());
        self.scene.lights.push(PunctualLight {
            name: name.clone(),
            position: camera.eye,
            kind: LightKind::Spot {
                direction: camera.forward,
                inner_cone_rad: ADDED_INNER_CONE_DEG.to_radians(),
                outer_cone_rad: ADDED_OUTER_CONE_DEG.to_radians(),
            },
            color: [1.0, 1.0, 1.0],
            intensity: ADDED_INTENSITY_CD,
            range: Some(ADDED_RANGE_M),
        });
        self.facts = SceneFacts::from(&self.scene);
        self.message = Some(format!("added {name} at the camera"));
    }

    /// Moves light `index` to `position`, metres (nothing where there is none).
    pub(super) fn move_light(&mut self, index: usize, position: glam::Vec3) {
        if let Some(light) = self.scene.lights.get_mut(index) {
            light.position = position;
        }
    }

    /// Removes light `index` (nothing where there is none).
    pub(super) fn remove_light(&mut self, index: usize) {
        if index < self.scene.lights.len() {
            let light = self.scene.lights.remove(index);
            self.facts = SceneFacts::from(&self.scene);
            self.message = Some(format!("removed {}", light.name));
        }
    }
}
