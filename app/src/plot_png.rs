//! Plots as PNG files: plotters' bitmap backend with egui's own font (nothing read from the
//! system), shared by `bench --plot` and `report`.

use std::path::Path;

use anyhow::Context as _;
use plotters::prelude::*;

/// The font every label uses.
pub const FONT: &str = "sans-serif";

/// Strong colours told apart on white, for lines and points by index.
pub const COLOURS: [RGBColor; 8] = [
    RGBColor(200, 30, 30),
    RGBColor(30, 130, 30),
    RGBColor(30, 70, 210),
    RGBColor(230, 130, 0),
    RGBColor(140, 30, 160),
    RGBColor(0, 150, 160),
    RGBColor(120, 80, 20),
    RGBColor(90, 90, 90),
];

pub type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// A drawing area of the bitmap backend.
pub type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// The chart's series labels in a box at `position`, in `size` point text.
pub fn legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    size: u32,
) -> DrawResult
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .label_font((FONT, size))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .draw()?;
    Ok(())
}

/// Draws a `size` picture on white with `draw` and writes it to the PNG `out`.
pub fn write_png(
    size: (u32, u32),
    out: &Path,
    draw: impl FnOnce(&Area<'_>) -> DrawResult,
) -> anyhow::Result<()> {
    // Registering twice fails harmlessly; a font that does not parse is a bug.
    let _ =
        plotters::style::register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT);
    let mut pixels = vec![0u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
        root.fill(&WHITE)
            .map_err(|e| anyhow::anyhow!("drawing {}: {e}", out.display()))?;
        draw(&root).map_err(|e| anyhow::anyhow!("drawing {}: {e}", out.display()))?;
        root.present()
            .map_err(|e| anyhow::anyhow!("drawing {}: {e}", out.display()))?;
    }
    let image = image::RgbImage::from_raw(size.0, size.1, pixels)
        .context("the plot's pixels do not fill its image")?;
    image
        .save(out)
        .with_context(|| format!("writing {}", out.display()))
}
