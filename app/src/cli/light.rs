//! `--light`: which light casts the shadows, the sun or one of the scene's point or spot
//! lights.

use anyhow::bail;
use render_core::frame::FrameSettings;
use render_core::scene::{PointShadow, Scene};

use super::ViewArgs;

/// `--light`: the sun, the scene's light of an index (of every point and spot light), or its
/// spot light of an index (of its spots alone).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightArg {
    Sun,
    Light(usize),
    Spot(usize),
}

/// `sun`, `point`, `point:N` (the Nth light), `spot` or `spot:N` (the Nth spot light).
pub(super) fn parse_light(s: &str) -> Result<LightArg, String> {
    let index = |n: &str| {
        n.parse::<usize>()
            .map_err(|_| format!("`{n}` is not a light's index (point:0, point:1, spot:0, ...)"))
    };
    match s.split_once(':') {
        None if s == "sun" => Ok(LightArg::Sun),
        None if s == "point" => Ok(LightArg::Light(0)),
        None if s == "spot" => Ok(LightArg::Spot(0)),
        Some(("point", n)) => index(n).map(LightArg::Light),
        Some(("spot", n)) => index(n).map(LightArg::Spot),
        _ => Err(format!(
            "unknown light `{s}`: sun, point, point:N, spot or spot:N"
        )),
    }
}

impl ViewArgs {
    /// Sets the light `--light` asks for from `scene`'s lights.
    pub fn light_over(&self, settings: &mut FrameSettings, scene: &Scene) -> anyhow::Result<()> {
        settings.point_light = match self.light {
            None => return Ok(()),
            Some(LightArg::Sun) => None,
            Some(LightArg::Light(index)) => match PointShadow::of_scene(scene, index) {
                Some(light) => Some(light),
                None => bail!(
                    "--light point:{index}: {} has {} point and spot lights (glTF files give \
                     them with KHR_lights_punctual; builtin:corridor has one)",
                    scene.name,
                    scene.lights.len()
                ),
            },
            Some(LightArg::Spot(index)) => match PointShadow::spot_of_scene(scene, index) {
                Some(light) => Some(light),
                None => bail!(
                    "--light spot:{index}: {} has {} spot lights (glTF files give them with \
                     KHR_lights_punctual; builtin:city-night has its street lamps)",
                    scene.name,
                    scene.spot_lights().count()
                ),
            },
        };
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lights_parse_by_kind_and_index_and_a_wrong_one_names_what_is_allowed() {
        assert_eq!(parse_light("sun"), Ok(LightArg::Sun));
        assert_eq!(parse_light("point"), Ok(LightArg::Light(0)));
        assert_eq!(parse_light("point:3"), Ok(LightArg::Light(3)));
        assert_eq!(parse_light("spot"), Ok(LightArg::Spot(0)));
        assert_eq!(parse_light("spot:2"), Ok(LightArg::Spot(2)));
        let wrong = parse_light("torch").unwrap_err();
        assert!(wrong.contains("spot:N"), "{wrong}");
        let index = parse_light("spot:x").unwrap_err();
        assert!(index.contains("`x`"), "{index}");
    }
}
