//! `bench --sweep maps --plot FILE.png`: the sweep drawn as Rákos draws his figures (GPU Pro
//! 4, ch. 19, Figures 19.3 to 19.9): for each map size, the maps' GPU time against the number
//! of maps, a line per path and culling; beneath, the CPU time of recording them. The title
//! names the scene and the options that make it one figure or another (no rasterisation,
//! vertex work, copies of the scene, the sun's cascades).

use std::path::Path;

use plotters::prelude::*;

use crate::plot_png::{Area, COLOURS, DrawResult, FONT, legend, write_png};

/// One measured row of the sweep, as the plot reads it.
pub(super) struct PlotPoint {
    /// The line it belongs to: "atlas, culled both" and the like.
    pub series: String,
    /// Its colour (the path) and its line's style (the culling), by index.
    pub colour: usize,
    pub style: usize,
    pub size: u32,
    pub maps: u32,
    pub gpu_ms: Option<f64>,
    pub cpu_ms: Option<f64>,
}

const PANEL: (u32, u32) = (480, 340);

/// Draws `points` into the PNG `out`, under `title`.
pub(super) fn plot(points: &[PlotPoint], title: &str, out: &Path) -> anyhow::Result<()> {
    let mut sizes: Vec<u32> = points.iter().map(|p| p.size).collect();
    sizes.sort_unstable();
    sizes.dedup();
    let mut series: Vec<&PlotPoint> = Vec::new();
    for p in points {
        if !series.iter().any(|s| s.series == p.series) {
            series.push(p);
        }
    }
    if sizes.is_empty() {
        anyhow::bail!("--plot: the sweep measured nothing to plot");
    }
    let width = PANEL.0 * sizes.len() as u32;
    let height = 40 + 2 * PANEL.1;
    write_png((width, height), out, |root| {
        draw(root, (points, &sizes, &series), title)
    })
}

fn draw(
    root: &Area<'_>,
    (points, sizes, series): (&[PlotPoint], &[u32], &[&PlotPoint]),
    title: &str,
) -> DrawResult {
    let root = root.titled(title, (FONT, 22))?;
    let (gpu, cpu) = root.split_vertically(PANEL.1);
    let gpu_panels = gpu.split_evenly((1, sizes.len()));
    let cpu_panels = cpu.split_evenly((1, sizes.len()));
    for ((&size, gpu), cpu) in sizes.iter().zip(&gpu_panels).zip(&cpu_panels) {
        let at_size: Vec<&PlotPoint> = points.iter().filter(|p| p.size == size).collect();
        panel(
            gpu,
            (&at_size, series),
            (format!("{size}² maps: GPU time"), "maps + culling, ms"),
            |p| p.gpu_ms,
        )?;
        panel(
            cpu,
            (&at_size, series),
            (format!("{size}² maps: CPU recording"), "CPU ms"),
            |p| p.cpu_ms,
        )?;
    }
    Ok(())
}

/// One chart: `value` of each series against the number of maps, on a log2 axis (the counts
/// double), labelled 1, 2, 4, ...
fn panel(
    area: &Area<'_>,
    (points, series): (&[&PlotPoint], &[&PlotPoint]),
    (caption, y_label): (String, &str),
    value: fn(&PlotPoint) -> Option<f64>,
) -> DrawResult {
    let max_maps = points.iter().map(|p| p.maps).max().unwrap_or(1).max(2);
    let doublings = f64::from(max_maps).log2().ceil();
    let top = points
        .iter()
        .filter_map(|p| value(p))
        .fold(0.0f64, f64::max)
        .max(1e-3)
        * 1.1;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FONT, 16))
        .margin(10)
        .x_label_area_size(34)
        .y_label_area_size(52)
        .build_cartesian_2d(-0.2f64..doublings + 0.2, 0f64..top)?;
    chart
        .configure_mesh()
        .x_desc("maps")
        .y_desc(y_label)
        .label_style((FONT, 13))
        .x_labels(doublings as usize + 1)
        .x_label_formatter(&|x| format!("{:.0}", x.exp2()))
        .light_line_style(WHITE)
        .draw()?;
    for first in series {
        let mut line: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.series == first.series)
            .filter_map(|p| value(p).map(|v| (f64::from(p.maps.max(1)).log2(), v)))
            .collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        if line.is_empty() {
            continue;
        }
        let colour = COLOURS[first.colour % COLOURS.len()];
        // The style: a thin line with open circles, then ever thicker lines with triangles,
        // crosses and filled circles.
        let style = first.style % 4;
        let stroke = colour.stroke_width(1 + style as u32);
        chart
            .draw_series(LineSeries::new(line.clone(), stroke))?
            .label(first.series.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], stroke));
        let marker = |&(x, y): &(f64, f64)| -> DynElement<'static, BitMapBackend<'_>, (f64, f64)> {
            match style {
                0 => Circle::new((x, y), 4, colour.stroke_width(1)).into_dyn(),
                1 => TriangleMarker::new((x, y), 5, colour.filled()).into_dyn(),
                2 => Cross::new((x, y), 4, colour.stroke_width(2)).into_dyn(),
                _ => Circle::new((x, y), 4, colour.filled()).into_dyn(),
            }
        };
        chart.draw_series(line.iter().map(marker))?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperLeft, 12)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plot_has_a_panel_pair_per_size_and_draws_each_series() {
        let points: Vec<PlotPoint> = [256, 512]
            .into_iter()
            .flat_map(|size| {
                [1u32, 4, 16].into_iter().flat_map(move |maps| {
                    ["traditional, culled none", "atlas, culled both"]
                        .into_iter()
                        .enumerate()
                        .map(move |(i, series)| PlotPoint {
                            series: series.into(),
                            colour: 2 * i,
                            style: 3 * i,
                            size,
                            maps,
                            gpu_ms: Some(f64::from(maps) * (2.0 - i as f64)),
                            cpu_ms: Some(0.01 * f64::from(maps)),
                        })
                })
            })
            .collect();
        let dir = std::env::temp_dir().join(format!("shadowlab-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("maps.png");
        plot(&points, "hall: a test", &out).expect("plots");
        let image = image::open(&out).expect("a PNG").to_rgb8();
        assert_eq!(image.dimensions(), (2 * PANEL.0, 40 + 2 * PANEL.1));
        // Each series' colour is drawn: its line and its legend.
        for i in [0, 2] {
            let RGBColor(r, g, b) = COLOURS[i];
            let drawn = image.pixels().filter(|p| p.0 == [r, g, b]).count();
            assert!(drawn > 100, "series {i}: {drawn} pixels");
        }
        // Text was drawn (dark pixels beside the axes' lines), so the font registered.
        let dark = image
            .pixels()
            .filter(|p| p.0.iter().all(|&v| v < 60))
            .count();
        assert!(dark > 2_000, "{dark} dark pixels");
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(plot(&[], "empty", &out).is_err());
    }
}
