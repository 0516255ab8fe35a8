//! `--light`: which light casts the shadows, the sun or one of the scene's point lights.

use anyhow::bail;
use render_core::frame::FrameSettings;
use render_core::scene::{PointShadow, Scene};

use super::ViewArgs;

/// `--light`: the sun (`None`) or the scene's point light of this index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightArg(pub Option<usize>);

/// `sun`, `point` or `point:N` (the Nth point light).
pub(super) fn parse_light(s: &str) -> Result<LightArg, String> {
    match s.split_once(':') {
        None if s == "sun" => Ok(LightArg(None)),
        None if s == "point" => Ok(LightArg(Some(0))),
        Some(("point", n)) => n
            .parse()
            .map(|n| LightArg(Some(n)))
            .map_err(|_| format!("`{n}` is not a light's index (point:0, point:1, ...)")),
        _ => Err(format!("unknown light `{s}`: sun, point or point:N")),
    }
}

impl ViewArgs {
    /// Sets the light `--light` asks for from `scene`'s lights.
    pub fn light_over(&self, settings: &mut FrameSettings, scene: &Scene) -> anyhow::Result<()> {
        match self.light {
            None => {}
            Some(LightArg(None)) => settings.point_light = None,
            Some(LightArg(Some(index))) => {
                let Some(point) = PointShadow::of_scene(scene, index) else {
                    bail!(
                        "--light point:{index}: {} has {} point lights (glTF files give them \
                         with KHR_lights_punctual; builtin:corridor has one)",
                        scene.name,
                        scene.lights.len()
                    );
                };
                settings.point_light = Some(point);
            }
        }
        Ok(())
    }
}
