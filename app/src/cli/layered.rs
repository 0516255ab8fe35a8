//! The many-lights options: `--layered traditional|multiview|atlas` and `--lights N`.

use anyhow::bail;
use clap::Args;
use render_core::frame::{FrameSettings, ShadowSetup};
use render_core::shadow_view::{LayerCulling, LayeredPath, LayeredSettings};

/// How many lights cast shadows, and how their maps are rendered.
#[derive(Args, Debug, Default, Clone)]
pub struct LayeredArgs {
    /// Many lights (`--shadow lights`, which this implies): render the maps by a pass each
    /// (traditional), a multiview pass per group of maps (multiview), or one instanced draw
    /// per mesh into an atlas (atlas).
    #[arg(long, value_parser = parse_layered, value_name = "PATH")]
    pub layered: Option<LayeredPath>,
    /// Many lights: only the scene's first N lights shine and cast shadows (0: all).
    #[arg(long, value_name = "N")]
    pub lights: Option<u32>,
    /// Many lights: per-layer culling of triangles in compute before the maps are drawn:
    /// none, frustum (each view's), back-faces (a closed mesh's, away from the light) or both.
    #[arg(long, value_parser = parse_culling, value_name = "CULL")]
    pub layer_culling: Option<LayerCulling>,
    /// Many lights: the sun shines too, shadowed by cascades (`--cascades N` and its flags)
    /// that the same path renders with the lights' maps.
    #[arg(long)]
    pub sun_cascades: bool,
    /// Many lights, to measure the geometry stage (Rákos's Figure 19.4): every vertex lands
    /// outside its map after its work, so nothing is rasterised.
    #[arg(long)]
    pub no_raster: bool,
    /// Many lights, a heavier vertex stage (Rákos's Figure 19.6): this many rounds of
    /// skinning-like matrix products per vertex, 0 to 256.
    #[arg(long, value_name = "N")]
    pub vertex_work: Option<u32>,
}

impl LayeredArgs {
    /// Whether these ask for the many-lights technique (a many-lights option and no other
    /// setup).
    pub fn asks_for_lights(&self, shadow: Option<ShadowSetup>) -> bool {
        let any = self.layered.is_some()
            || self.lights.is_some()
            || self.layer_culling.is_some()
            || self.sun_cascades
            || self.no_raster
            || self.vertex_work.is_some();
        shadow == Some(ShadowSetup::Lights) || (shadow.is_none() && any)
    }

    /// The options into `settings`; any of them without `--shadow` picks `--shadow lights`.
    pub fn apply_to(
        &self,
        shadow: Option<ShadowSetup>,
        settings: &mut FrameSettings,
    ) -> anyhow::Result<()> {
        if let Some(path) = self.layered {
            settings.layered.path = path;
        }
        if shadow.is_none() && self.asks_for_lights(None) {
            settings.setup = ShadowSetup::Lights;
        }
        if let Some(lights) = self.lights {
            if lights > 1024 {
                bail!("--lights {lights}: at most 1024 lights (0 for all of the scene's)");
            }
            settings.layered.lights = lights;
        }
        if let Some(culling) = self.layer_culling {
            settings.layered.culling = culling;
        }
        if self.sun_cascades {
            settings.layered.sun = true;
        }
        if self.no_raster {
            settings.layered.load.no_raster = true;
        }
        if let Some(work) = self.vertex_work {
            if work > 256 {
                bail!("--vertex-work {work}: at most 256 rounds");
            }
            settings.layered.load.vertex_work = work;
        }
        Ok(())
    }
}

/// The range of `--shadow-res` for the setup the options ask for: each light's map may be
/// smaller than the sun's.
pub fn resolution_range(lights: bool) -> std::ops::RangeInclusive<u32> {
    if lights {
        LayeredSettings::MIN_RESOLUTION..=LayeredSettings::MAX_RESOLUTION
    } else {
        render_core::shadow_view::ShadowSettings::MIN_RESOLUTION
            ..=render_core::shadow_view::ShadowSettings::MAX_RESOLUTION
    }
}

fn parse_layered(s: &str) -> Result<LayeredPath, String> {
    s.parse()
}

fn parse_culling(s: &str) -> Result<LayerCulling, String> {
    s.parse()
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;
    use crate::cli::{Cli, Command};

    fn settings(args: &[&str]) -> anyhow::Result<FrameSettings> {
        let head = ["shadowlab", "shot", "--out", "a.png"];
        let cli = Cli::try_parse_from(head.iter().chain(args)).expect("parses");
        let Some(Command::Shot(shot)) = cli.command else {
            panic!("a shot");
        };
        shot.view.settings_over(&FrameSettings::default())
    }

    #[test]
    fn layered_picks_the_lights_technique_and_its_path_and_the_map_may_be_small() {
        let s = settings(&["--layered", "atlas", "--shadow-res", "256"]).unwrap();
        assert_eq!(s.setup, ShadowSetup::Lights);
        assert_eq!(s.layered.path, LayeredPath::Atlas);
        assert_eq!(s.shadow.resolution, 256);
        let s = settings(&["--shadow", "lights", "--lights", "4"]).unwrap();
        assert_eq!((s.setup, s.layered.lights), (ShadowSetup::Lights, 4));
        assert_eq!(s.layered.culling, LayerCulling::Both);
        let s = settings(&[
            "--layer-culling",
            "frustum",
            "--sun-cascades",
            "--no-raster",
            "--vertex-work",
            "8",
        ])
        .unwrap();
        assert_eq!(s.layered.culling, LayerCulling::Frustum);
        assert_eq!(
            s.setup,
            ShadowSetup::Lights,
            "a many-lights option picks them"
        );
        assert!(s.layered.sun && s.cascaded_sun() && s.exact_truth_applies());
        assert!(s.layered.load.no_raster);
        assert_eq!(s.layered.load.vertex_work, 8);
        assert!(settings(&["--vertex-work", "1000"]).is_err());
        // The sun's maps keep their range.
        let e = settings(&["--shadow-res", "256"]).unwrap_err();
        assert!(e.to_string().contains("--shadow-res 256"), "{e}");
        let e = Cli::try_parse_from(["shadowlab", "shot", "--out", "a.png", "--layered", "layers"])
            .unwrap_err();
        assert!(e.to_string().contains("'layers'"), "{e}");
    }
}
