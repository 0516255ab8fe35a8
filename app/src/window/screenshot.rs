//! Screenshots from the window: the 3D view (with the overlays' legend) or the whole window as
//! PNG, with the frame's stats as JSON beside it.

use std::path::Path;

use anyhow::Context as _;
use render_core::frame::compare::CompareRow;
use render_core::gpu::read_texture;

use super::Running;
use super::surface::read_capture;
use crate::headless::{stats_json, write_png};
use crate::legend_image::with_legend;

impl Running {
    /// Writes the 3D view (or, with "include panel", the whole window) as PNG plus stats JSON.
    /// Blocks for the readback: a one-off user action, not part of the frame loop.
    pub(super) fn save_screenshot(
        &mut self,
        window_capture: Option<&wgpu::Texture>,
    ) -> anyhow::Result<()> {
        let report = self
            .last_report
            .as_ref()
            .context("no frame has been rendered yet")?;
        let image = if let Some(texture) = window_capture {
            read_capture(&self.ctx, texture)?
        } else {
            let targets = self
                .renderer
                .targets()
                .context("no frame has been rendered yet")?;
            let view = read_texture(&self.ctx, &targets.color, wgpu::TextureAspect::All)?
                .into_rgba_image()
                .context("colour target is not RGBA8")?;
            // The window's capture has the legend egui drew; the view alone gets it here.
            with_legend(&self.ctx, &view, &self.settings)?
        };
        let stamp = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        let slug: String = self
            .facts
            .name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let slug = slug
            .rsplit('_')
            .next()
            .filter(|s| !s.is_empty())
            .unwrap_or("scene")
            .to_owned();
        let folder = Path::new(&self.screenshot_settings.folder);
        let png = folder.join(format!(
            "shadowlab-{slug}-{stamp}-{}.png",
            report.frame_index
        ));
        write_png(&image, &png)?;
        let mut stats = stats_json(
            &self.scene,
            &self.settings,
            &self.controller.camera,
            report,
            &self.ctx,
            self.last_frame_ms,
        );
        if let Some(compare) = &self.compare {
            stats["compare"] = compare_rows(compare.rows());
        }
        let json_path = png.with_extension("json");
        std::fs::write(&json_path, serde_json::to_string_pretty(&stats)?)
            .with_context(|| format!("writing {}", json_path.display()))?;
        self.last_screenshot = Some(png.display().to_string());
        self.message = Some(format!(
            "Saved {} and {}",
            png.display(),
            json_path.display()
        ));
        Ok(())
    }
}

/// The compare table's rows as the screenshot's stats carry them: each method's counts, error
/// and GPU times, and whether it was computed for an earlier view.
fn compare_rows(rows: &[CompareRow]) -> serde_json::Value {
    rows.iter()
        .map(|r| {
            serde_json::json!({
                "method": r.method.name(),
                "casters_drawn": r.casters_rendered,
                "triangles": r.triangles,
                "casters_oracle": r.casters_oracle,
                "error_px": r.error_px,
                "shadow_ms": r.shadow_ms,
                "culling_ms": r.culling_ms,
                "stale": r.stale,
            })
        })
        .collect()
}
