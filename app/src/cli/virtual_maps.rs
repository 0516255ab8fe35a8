//! The virtual maps' options: `--pages N`, `--levels N`, `--cache on|off`, `--finest-texel M`,
//! `--lod-bias OCTAVES`, `--separate-static on|off` and `--receiver-mask on|off`.

use anyhow::bail;
use clap::Args;
use render_core::frame::{FrameSettings, ShadowSetup};
use render_core::shadow_view::VirtualSettings;

/// The pool, the clipmap and the cache of `--shadow virtual`.
#[derive(Args, Debug, Default, Clone)]
pub struct VirtualArgs {
    /// Virtual maps (`--shadow virtual`, which this implies): physical pages in the pool, 16
    /// to 4096, 64 KiB each (default 1024: 64 MiB, as four cascades of 2048).
    #[arg(long, value_name = "N")]
    pub pages: Option<u32>,
    /// Virtual maps: clipmap levels, 1 to 24, each with texels twice the last's (default 16);
    /// from a point or spot light (`--light`), mips per face of its cube (or of the spot's
    /// cone), the coarsest kept: 8 (the most) from 16,384 texels square, 6 from 4096.
    #[arg(long, value_name = "N")]
    pub levels: Option<u32>,
    /// Virtual maps: keep drawn pages across frames until something moves through them (on,
    /// the default) or draw every needed page each frame (off).
    #[arg(long, value_parser = parse_on_off, value_name = "on|off")]
    pub cache: Option<bool>,
    /// Virtual maps: the finest level's texel in metres (default 0.002).
    #[arg(long, value_name = "M")]
    pub finest_texel: Option<f32>,
    /// Virtual maps: octaves added to the level resolution matching picks, -4 to 4 (above 0
    /// coarser; default -0.5, as Unreal's).
    #[arg(long, value_name = "OCTAVES", allow_hyphen_values = true)]
    pub lod_bias: Option<f32>,
    /// Virtual maps: keep static casters' depths apart from movable ones' (on), so a moving
    /// object draws only the movable casters of the pages it touches again, at twice the
    /// pool's memory; or one layer for all (off, the default).
    #[arg(long, value_parser = parse_on_off, value_name = "on|off")]
    pub separate_static: Option<bool>,
    /// Virtual maps: cull casters per block of 16 x 16 texels that visible pixels read, not
    /// per page (on; Unreal 5.6's receiver mask): every caster with one layer per page, the
    /// movable casters with static casters apart (all of them in frames that draw every
    /// page); a page it leaves partial is drawn again the next frame. Off by default.
    #[arg(long, value_parser = parse_on_off, value_name = "on|off")]
    pub receiver_mask: Option<bool>,
    /// Virtual maps with static casters apart: a movable caster wholly behind a cached page's
    /// static casters neither makes the page's movable layer stale nor is drawn into it (on,
    /// the default; exact), or every moved box refreshes the pages it touches (off).
    #[arg(long, value_parser = parse_on_off, value_name = "on|off")]
    pub static_occlusion: Option<bool>,
}

impl VirtualArgs {
    fn any(&self) -> bool {
        self.pages.is_some()
            || self.levels.is_some()
            || self.cache.is_some()
            || self.finest_texel.is_some()
            || self.lod_bias.is_some()
            || self.separate_static.is_some()
            || self.receiver_mask.is_some()
            || self.static_occlusion.is_some()
    }

    /// The options into `settings`; any of them without `--shadow` picks `--shadow virtual`.
    pub fn apply_to(
        &self,
        shadow: Option<ShadowSetup>,
        settings: &mut FrameSettings,
    ) -> anyhow::Result<()> {
        if shadow.is_none() && self.any() {
            settings.setup = ShadowSetup::Virtual;
        }
        let s = &mut settings.virtual_maps;
        if let Some(pages) = self.pages {
            let range = VirtualSettings::MIN_PAGES..=VirtualSettings::MAX_PAGES;
            if !range.contains(&pages) {
                bail!(
                    "--pages {pages} is outside {} to {}",
                    range.start(),
                    range.end()
                );
            }
            s.pages = pages;
        }
        if let Some(levels) = self.levels {
            if !(1..=VirtualSettings::MAX_LEVELS).contains(&levels) {
                bail!(
                    "--levels {levels} is outside 1 to {}",
                    VirtualSettings::MAX_LEVELS
                );
            }
            s.levels = levels;
        }
        if let Some(cache) = self.cache {
            s.cache = cache;
        }
        if let Some(apart) = self.separate_static {
            s.separate_static = apart;
        }
        if let Some(mask) = self.receiver_mask {
            s.receiver_mask = mask;
        }
        if let Some(occlusion) = self.static_occlusion {
            s.static_occlusion = occlusion;
        }
        if let Some(texel) = self.finest_texel {
            if !(texel.is_finite() && texel > 0.0 && texel <= 100.0) {
                bail!("--finest-texel must be a size above 0 and at most 100 metres");
            }
            s.finest_texel_m = texel;
        }
        if let Some(bias) = self.lod_bias {
            if !(bias.is_finite() && (-4.0..=4.0).contains(&bias)) {
                bail!("--lod-bias {bias} is outside -4 to 4 octaves");
            }
            s.lod_bias = bias;
        }
        Ok(())
    }
}

fn parse_on_off(s: &str) -> Result<bool, String> {
    match s {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("expected on or off, got '{s}'")),
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Parser)]
    struct Cli {
        #[arg(long)]
        shadow: Option<ShadowSetup>,
        #[command(flatten)]
        args: VirtualArgs,
    }

    fn settings(line: &[&str]) -> anyhow::Result<FrameSettings> {
        let cli = Cli::try_parse_from(std::iter::once("x").chain(line.iter().copied()))?;
        let mut s = FrameSettings::default();
        if let Some(shadow) = cli.shadow {
            s.setup = shadow;
        }
        cli.args.apply_to(cli.shadow, &mut s)?;
        Ok(s)
    }

    #[test]
    fn the_options_set_the_pool_levels_and_cache_and_imply_virtual() {
        let s = settings(&["--pages", "256", "--levels", "12", "--cache", "off"]).unwrap();
        assert_eq!(s.setup, ShadowSetup::Virtual);
        assert_eq!((s.virtual_maps.pages, s.virtual_maps.levels), (256, 12));
        assert!(!s.virtual_maps.cache);
        let s = settings(&["--shadow", "virtual", "--lod-bias", "-0.5"]).unwrap();
        assert!((s.virtual_maps.lod_bias + 0.5).abs() < 1e-9);
        assert!(s.virtual_maps.cache);
        assert!(!s.virtual_maps.separate_static);
        let s = settings(&["--separate-static", "on"]).unwrap();
        assert_eq!(s.setup, ShadowSetup::Virtual);
        assert!(s.virtual_maps.separate_static);
        assert!(settings(&["--separate-static", "yes"]).is_err());
        let s = settings(&["--receiver-mask", "on", "--cache", "off"]).unwrap();
        assert!(s.virtual_maps.receiver_mask && !s.virtual_maps.cache);
        assert!(s.virtual_maps.static_occlusion, "on by default");
        let s = settings(&["--separate-static", "on", "--static-occlusion", "off"]).unwrap();
        assert!(s.virtual_maps.separate_static && !s.virtual_maps.static_occlusion);
        assert!(settings(&["--static-occlusion", "maybe"]).is_err());
    }

    #[test]
    fn out_of_range_options_name_the_flag() {
        for (line, flag) in [
            (&["--pages", "8"][..], "--pages"),
            (&["--levels", "30"][..], "--levels"),
            (&["--finest-texel", "0"][..], "--finest-texel"),
            (&["--lod-bias", "9"][..], "--lod-bias"),
        ] {
            let e = settings(line).unwrap_err().to_string();
            assert!(e.contains(flag), "{e}");
        }
        assert!(settings(&["--cache", "maybe"]).is_err());
    }
}
