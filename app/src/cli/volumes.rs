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
