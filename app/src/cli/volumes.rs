//! The `--volume-*` options: how shadow volumes are clamped, counted and culled.

use anyhow::bail;
use render_core::frame::FrameSettings;
use render_core::volumes::{VolumeClamp, VolumePassChoice, VolumeSettings};

use super::ViewArgs;

impl ViewArgs {
    /// The `--volume-*` options into `settings`; an error names the option out of range.
    pub(super) fn volumes_into(&self, settings: &mut FrameSettings) -> anyhow::Result<()> {
        if let Some(clamp) = self.volume_clamp {
            settings.volumes.clamp = clamp;
        }
        if let Some(pass) = self.volume_pass {
            settings.volumes.pass = pass;
        }
        if let Some(steps) = self.volume_cull_steps {
            if steps == 0 {
                bail!("--volume-cull-steps must be at least 1");
            }
            settings.volumes.cull_steps = Some(steps);
        }
        if let Some(points) = self.volume_cell_points {
            settings.volumes.cell_points = Some(points);
        }
        if let Some(lanes) = self.volume_cull_lanes {
            if !(1..=32).contains(&lanes) {
                bail!("--volume-cull-lanes must be from 1 to 32, not {lanes}");
            }
            settings.volumes.cull_lanes = Some(lanes);
        }
        if let Some(pixels) = self.volume_vertex_pixels {
            settings.volumes.vertex_pixels = Some(pixels);
        }
        if let Some(slices) = self.volume_slices {
            let most = VolumeSettings::MAX_SLICES;
            if !(1..=most).contains(&slices) {
                bail!("--volume-slices {slices} is outside 1 to {most}");
            }
            settings.volumes.slices = slices;
        }
        if self.no_volume_strips {
            settings.volumes.strips = false;
        }
        Ok(())
    }
}

pub(super) fn parse_volume_clamp(s: &str) -> Result<VolumeClamp, String> {
    s.parse()
}

pub(super) fn parse_volume_pass(s: &str) -> Result<VolumePassChoice, String> {
    s.parse()
}

#[cfg(test)]
mod tests {
    use clap::Parser;
    use render_core::frame::FrameSettings;
    use render_core::volumes::VolumeClamp;

    use super::super::{Cli, Command};

    fn settings(flags: &[&str]) -> anyhow::Result<FrameSettings> {
        let cli = Cli::try_parse_from(["shadowlab", "shot", "--out", "a.png"].iter().chain(flags))
            .expect("flags parse");
        let Some(Command::Shot(shot)) = cli.command else {
            panic!("a shot");
        };
        shot.view.settings_over(&FrameSettings::default())
    }

    #[test]
    fn the_volume_options_reach_the_settings_or_name_what_is_out_of_range() {
        let set = settings(&[
            "--volume-clamp",
            "boxes",
            "--volume-cull-lanes",
            "8",
            "--volume-cull-steps",
            "256",
            "--no-volume-strips",
        ])
        .expect("in range");
        let v = set.volumes;
        assert_eq!(
            (v.clamp, v.cull_lanes, v.cull_steps, v.strips),
            (VolumeClamp::Boxes, Some(8), Some(256), false)
        );
        assert!(settings(&[]).expect("defaults").volumes.strips);
        for (flag, value) in [
            ("--volume-cull-lanes", "33"),
            ("--volume-cull-lanes", "0"),
            ("--volume-cull-steps", "0"),
            ("--volume-slices", "40"),
        ] {
            let error = settings(&[flag, value]).expect_err(flag).to_string();
            assert!(error.contains(flag), "{error}");
        }
    }
}
