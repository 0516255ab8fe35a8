//! A sweep's part of the report: its rows run along the path as the families' are, and its
//! section (what it varies, the table, a plot per measure with a line per method or path).

use std::path::Path;

use indicatif::ProgressBar;
use render_core::geom::Camera;
use render_core::scene::CameraPath;

use super::document::Block;
use super::plots::{self, Series};
use super::sweeps::{ReportSweep, SweepRow};
use super::{ReportRow, against_truth, row, table};
use crate::bench::{BenchRow, RunOptions, run_path};
use crate::headless::Session;

/// Where a row sits in its sweep.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SweptAt {
    pub sweep: &'static str,
    /// The swept parameter's value, the x axis.
    pub point: String,
    /// The line it is on: a method, a path, a clamping.
    pub series: String,
}

/// Runs `rows` of `sweep`, each along the path as `bench` would, the speed-ups against the
/// sweep's first row.
pub fn run(
    session: &mut Session,
    (path, template): (&CameraPath, &Camera),
    (sweep, rows): (ReportSweep, &[SweepRow]),
    options: &RunOptions,
    bar: &ProgressBar,
) -> anyhow::Result<Vec<ReportRow>> {
    let family = sweep.family();
    let mut out = Vec::new();
    for r in rows {
        let label = format!("{} / {}", r.point, r.series);
        bar.set_message(format!("{} sweep: {label}", sweep.name()));
        let mut done = |_| bar.inc(1);
        let reports = run_path(session, (path, template), &r.settings, options, &mut done)?;
        if bar.is_hidden() {
            eprintln!("  {} sweep: {label} done", sweep.name());
        }
        let mut row = row(family, &label, r.settings.method.name(), &reports);
        row.swept = Some(SweptAt {
            sweep: sweep.name(),
            point: r.point.clone(),
            series: r.series.clone(),
        });
        out.push(row);
    }
    super::speed_ups_against_first(&mut out);
    Ok(out)
}

/// The sweep's section: what it varies, its table, and a plot per measure.
pub fn blocks(out: &Path, sweep: ReportSweep, rows: &[&ReportRow], blocks: &mut Vec<Block>) {
    let described = sweep.description();
    let title = described.split(':').next().unwrap_or(sweep.name());
    blocks.push(Block::Heading(3, format!("Sweep: {title}")));
    blocks.push(Block::Paragraph(format!("{described}.")));
    blocks.push(table(rows, false));
    let mut points: Vec<&str> = Vec::new();
    let mut lines: Vec<&str> = Vec::new();
    for r in rows {
        let at = at(r);
        if !points.contains(&at.point.as_str()) {
            points.push(&at.point);
        }
        if !lines.contains(&at.series.as_str()) {
            lines.push(&at.series);
        }
    }
    let summaries: Vec<&BenchRow> = rows.iter().map(|r| &r.row).collect();
    let exact = against_truth(&summaries);
    for measure in sweep.measures() {
        let series: Vec<Series> = lines
            .iter()
            .map(|&line| Series {
                label: line.to_owned(),
                values: points
                    .iter()
                    .map(|&point| {
                        rows.iter()
                            .find(|r| at(r).point == point && at(r).series == line)
                            .and_then(|r| measure.value(&r.row, exact))
                    })
                    .collect(),
            })
            .collect();
        let y_desc = measure.y_desc(exact);
        let file = format!("sweep-{}-{}.png", sweep.name(), measure.name());
        let caption = format!("{title}: {y_desc}");
        let ticks: Vec<String> = points.iter().map(|&p| p.to_owned()).collect();
        match plots::across(
            &series,
            &ticks,
            (&caption, sweep.x_desc(), y_desc),
            &out.join(&file),
        ) {
            Ok(()) => blocks.push(Block::Image(file, caption)),
            // A measure this adapter could not give (GPU time) is said, not drawn empty.
            Err(e) => blocks.push(Block::Paragraph(format!("Not drawn: {e}."))),
        }
    }
}

/// Where a sweep's row sits (a sweep's rows always say).
fn at(row: &ReportRow) -> &SweptAt {
    row.swept
        .as_ref()
        .expect("a sweep's rows say where they sit")
}
