//! Plots as PNG files: plotters' bitmap backend with egui's own font (nothing read from the
//! system), shared by `bench --plot` and `report`; lines across named ticks.

use std::path::Path;

use anyhow::Context as _;
use plotters::prelude::*;

/// A plot's picture, pixels.
pub const SIZE: (u32, u32) = (960, 480);

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

/// One line across a plot's ticks (frames along a path, a sweep's values): a value per tick
/// (none where it was not measured).
pub struct Series {
    pub label: String,
    pub values: Vec<Option<f64>>,
}

/// `series` across the values `ticks` names (a sweep's settings, the frames of a path), a
/// line each, into the PNG `out`.
pub fn across(
    series: &[Series],
    ticks: &[String],
    (title, x_label, y_label): (&str, &str, &str),
    out: &Path,
) -> anyhow::Result<()> {
    if ticks.is_empty() || series.iter().all(|s| s.values.iter().all(Option::is_none)) {
        anyhow::bail!("{title}: nothing was measured");
    }
    write_png(SIZE, out, |root| {
        draw_lines(root, series, ticks, (title, x_label, y_label))
    })
}

/// The plot's values from `bottom` to `top`: zero in view, and below it where a value is
/// (time saved can be negative); a tenth to spare, and above that the legend's rows
/// ([`LEGEND_ROW_PX`] each in a plot of [`PLOT_PX`]), so the legend covers no line.
fn value_range(series: &[Series]) -> (f64, f64) {
    let values = || series.iter().flat_map(|s| s.values.iter().flatten());
    let bottom = values().fold(0.0f64, |a, &b| a.min(b)) * 1.1;
    let highest = values().fold(0.0f64, |a, &b| a.max(b)).max(1e-3) * 1.1;
    let legend = legend_share(series.len());
    (
        bottom,
        highest + (highest - bottom) * legend / (1.0 - legend),
    )
}

/// The share of the plot's height the legend takes over `lines` lines (at most half).
fn legend_share(lines: usize) -> f64 {
    (f64::from(LEGEND_ROW_PX) * (lines as f64 + 1.0) / f64::from(PLOT_PX)).min(0.5)
}

/// A legend row's height and the plot's (the picture less its caption and axis labels),
/// pixels.
const LEGEND_ROW_PX: u32 = 18;
const PLOT_PX: u32 = SIZE.1 - 100;

fn draw_lines(
    root: &Area<'_>,
    series: &[Series],
    ticks: &[String],
    (title, x_label, y_label): (&str, &str, &str),
) -> DrawResult {
    let (bottom, top) = value_range(series);
    let count = ticks.len() as i32;
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 20))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(60)
        .build_cartesian_2d((0..count - 1).into_segmented(), bottom..top)?;
    // Every tick named while they fit; past 16, every k-th.
    let every = ticks.len().div_ceil(16).max(1);
    let tick_name = |value: &SegmentValue<i32>| match value {
        SegmentValue::CenterOf(k) if (*k as usize).is_multiple_of(every) => {
            ticks.get(*k as usize).cloned().unwrap_or_default()
        }
        _ => String::new(),
    };
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style((FONT, 14))
        .x_labels(ticks.len() + 1)
        .x_label_formatter(&tick_name)
        .light_line_style(WHITE)
        .draw()?;
    for (i, s) in series.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        // Past the palette, lines repeat its colours thicker.
        let stroke = colour.stroke_width(1 + (i / COLOURS.len()) as u32 * 2);
        let line: Vec<(SegmentValue<i32>, f64)> = s
            .values
            .iter()
            .enumerate()
            .filter_map(|(k, v)| v.map(|v| (SegmentValue::CenterOf(k as i32), v)))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), stroke))?
            .label(s.label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], stroke));
        chart.draw_series(line.into_iter().map(|p| Circle::new(p, 3, colour.filled())))?;
    }
    // The legend on the side away from the highest point.
    let highest = series
        .iter()
        .flat_map(|s| s.values.iter().enumerate())
        .filter_map(|(k, v)| v.map(|v| (k, v)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(0, |(k, _)| k);
    let position = if highest * 2 >= ticks.len() {
        SeriesLabelPosition::UpperLeft
    } else {
        SeriesLabelPosition::UpperRight
    };
    legend(&mut chart, position, 13)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_legend_sits_above_every_line() {
        let series: Vec<Series> = (0..7)
            .map(|i| Series {
                label: format!("line {i}"),
                values: vec![Some(367.0), Some(-105.0 + f64::from(i)), None],
            })
            .collect();
        let (bottom, top) = value_range(&series);
        assert!(bottom <= -105.0 * 1.1 + 1e-9, "{bottom}");
        // The legend's lower edge, in values: seven rows and a margin below the top.
        let legend_bottom = top - (top - bottom) * legend_share(7);
        assert!(legend_bottom >= 367.0 * 1.1 - 1e-9, "{legend_bottom} {top}");
        let (_, alone) = value_range(&series[..1]);
        assert!(alone < top, "one line needs less room than seven");
    }
}
