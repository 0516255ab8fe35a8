//! The report's plots: a figure along the camera path per row (Bittner's Table 3 as curves),
//! and speed against error, a point per row with the Pareto front marked.

use std::path::Path;

use plotters::prelude::*;

use crate::plot_png::{Area, COLOURS, DrawResult, FONT, legend, write_png};
pub use crate::plot_png::{Series, across};

/// One row of a family as a point: its cost and its error.
#[derive(Clone, Debug)]
pub struct Point {
    pub label: String,
    pub x: f64,
    pub y: f64,
}

use crate::plot_png::SIZE;

/// `series` against the frame index, a line each, into the PNG `out`.
pub fn along_path(
    series: &[Series],
    (title, y_label): (&str, &str),
    out: &Path,
) -> anyhow::Result<()> {
    let frames = series.iter().map(|s| s.values.len()).max().unwrap_or(0);
    let ticks: Vec<String> = (0..frames).map(|k| k.to_string()).collect();
    across(
        series,
        &ticks,
        (title, "frame along the path", y_label),
        out,
    )
}

/// The points no other point beats in both cost and error (lower is better in both), by
/// index, cheapest first.
pub fn pareto_front(points: &[Point]) -> Vec<usize> {
    let mut front: Vec<usize> = (0..points.len())
        .filter(|&i| {
            let p = &points[i];
            !points
                .iter()
                .any(|q| q.x <= p.x && q.y <= p.y && (q.x < p.x || q.y < p.y))
        })
        .collect();
    front.sort_by(|&a, &b| points[a].x.total_cmp(&points[b].x));
    front
}

/// `points` as a scatter with their labels, the Pareto front filled and joined, into `out`.
pub fn speed_against(
    points: &[Point],
    (title, x_label, y_label): (&str, &str, &str),
    out: &Path,
) -> anyhow::Result<()> {
    if points.is_empty() {
        anyhow::bail!("{title}: nothing to plot");
    }
    write_png(SIZE, out, |root| {
        draw_speed_against(root, points, (title, x_label, y_label))
    })
}

fn draw_speed_against(
    root: &Area<'_>,
    points: &[Point],
    (title, x_label, y_label): (&str, &str, &str),
) -> DrawResult {
    let max = |f: fn(&Point) -> f64| points.iter().map(f).fold(0.0f64, f64::max).max(1e-3) * 1.15;
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 20))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(60)
        .build_cartesian_2d(0f64..max(|p| p.x), 0f64..max(|p| p.y))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style((FONT, 14))
        .light_line_style(WHITE)
        .draw()?;
    let front = pareto_front(points);
    let front_colour = COLOURS[0];
    chart
        .draw_series(LineSeries::new(
            front.iter().map(|&i| (points[i].x, points[i].y)),
            front_colour.stroke_width(2),
        ))?
        .label("Pareto front: no row is both faster and more exact")
        .legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 18, y)], front_colour.stroke_width(2))
        });
    // Labels beside their points, in turn above, below, and left of them among points of a
    // height, so rows with the same error stay readable.
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        points[a]
            .y
            .total_cmp(&points[b].y)
            .then(points[a].x.total_cmp(&points[b].x))
    });
    for (k, &i) in order.iter().enumerate() {
        let p = &points[i];
        let on_front = front.contains(&i);
        let colour = if on_front { front_colour } else { COLOURS[2] };
        let style = if on_front {
            colour.filled()
        } else {
            colour.stroke_width(2)
        };
        // Right of the point, above then below; then left of it, above then below.
        let left = -7 - (p.label.chars().count() as f64 * 6.5) as i32;
        let label_at = [(7, -16), (7, 4), (left, -16), (left, 4)][k % 4];
        chart.draw_series(std::iter::once(
            EmptyElement::at((p.x, p.y))
                + Circle::new((0, 0), 5, style)
                + Text::new(
                    p.label.clone(),
                    label_at,
                    (FONT, 13).into_font().color(&BLACK),
                ),
        ))?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperRight, 13)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(label: &str, x: f64, y: f64) -> Point {
        Point {
            label: label.into(),
            x,
            y,
        }
    }

    #[test]
    fn the_front_keeps_the_points_nothing_beats_in_both() {
        let points = [
            point("slow exact", 9.0, 0.0),
            point("fast wrong", 1.0, 50.0),
            point("beaten", 9.5, 10.0),
            point("middle", 4.0, 5.0),
            point("tie of middle", 4.0, 5.0),
        ];
        // Equal points do not beat each other; the one beaten by the middle is out.
        assert_eq!(pareto_front(&points), vec![1, 3, 4, 0]);
    }

    #[test]
    fn both_plots_draw_their_points_and_lines() {
        let dir =
            std::env::temp_dir().join(format!("shadowlab-report-plots-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let series = [
            Series {
                label: "vfc".into(),
                values: vec![Some(2.0), Some(3.0), None, Some(2.5)],
            },
            Series {
                label: "frag".into(),
                values: vec![Some(1.0), Some(1.5), Some(1.2), Some(1.1)],
            },
        ];
        let along = dir.join("along.png");
        along_path(&series, ("frame time", "GPU ms"), &along).unwrap();
        let image = image::open(&along).unwrap().to_rgb8();
        for colour in &COLOURS[..2] {
            let drawn = image
                .pixels()
                .filter(|p| p.0 == [colour.0, colour.1, colour.2])
                .count();
            assert!(drawn > 100, "{colour:?}: {drawn} pixels");
        }
        let speed = dir.join("speed.png");
        let points = [
            point("vfc", 3.0, 0.0),
            point("frag", 1.0, 0.0),
            point("none", 5.0, 2.0),
        ];
        speed_against(&points, ("speed", "ms", "error px"), &speed).unwrap();
        let image = image::open(&speed).unwrap().to_rgb8();
        let front = COLOURS[0];
        let red = image
            .pixels()
            .filter(|p| p.0 == [front.0, front.1, front.2])
            .count();
        assert!(red > 50, "the front is drawn: {red} pixels");
        assert!(speed_against(&[], ("empty", "x", "y"), &speed).is_err());
    }
}
