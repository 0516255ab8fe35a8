//! `bench --sweep slices --plot FILE.png`: Lloyd et al.'s Figure 9, discrete clamping's GPU
//! times against its number of slicing planes. "The savings are calculated as the standard
//! shadow volume rendering time minus the combined time for clamping and rendering of CC
//! shadow volumes": here standard volumes' whole shadow pass (silhouettes, the surface's
//! depth, the stencil) minus the clamped row's, whose silhouettes pass holds its receiver
//! grid and its cull and clamp.

use std::path::Path;

use render_core::frame::pass_label;

use super::sweeps::STANDARD_VOLUMES;
use super::{BenchRow, median};
use crate::plot_png::{Series, across};

/// The lines of the figure from the sweep's `rows` (standard volumes' first), `baseline`
/// the method whose standard row the others save against, and the slices' labels.
fn series(rows: &[BenchRow], baseline: &str) -> anyhow::Result<(Vec<Series>, Vec<String>)> {
    let standard = rows
        .iter()
        .find(|r| r.setting == STANDARD_VOLUMES && r.method == baseline)
        .and_then(|r| r.shadow_pass_ms)
        .ok_or_else(|| {
            anyhow::anyhow!(
                "--plot: standard volumes' shadow pass was not timed (no GPU timestamps)"
            )
        })?;
    let sliced: Vec<&BenchRow> = rows
        .iter()
        .filter(|r| r.setting != STANDARD_VOLUMES)
        .collect();
    let mut ticks: Vec<String> = Vec::new();
    let mut methods: Vec<&str> = Vec::new();
    for row in &sliced {
        if !ticks.contains(&row.setting) {
            ticks.push(row.setting.clone());
        }
        if !methods.contains(&row.method.as_str()) {
            methods.push(&row.method);
        }
    }
    let mut lines = vec![Series {
        label: format!("standard volumes, {baseline}: shadow pass"),
        values: vec![Some(standard); ticks.len()],
    }];
    for method in methods {
        let at = |tick: &String| {
            sliced
                .iter()
                .find(|r| &r.setting == tick && r.method == method)
        };
        let line = |label: &str, value: &dyn Fn(&BenchRow) -> Option<f64>| Series {
            label: format!("{method}: {label}"),
            values: ticks.iter().map(|t| at(t).and_then(|r| value(r))).collect(),
        };
        // The stencil pass as the report's slices plot takes it.
        lines.push(line("stencil pass", &|r| {
            median(r.volume_pass_frames.clone())
        }));
        lines.push(line("cull + clamp", &clamping_ms));
        lines.push(line("saved", &|r| r.shadow_pass_ms.map(|ms| standard - ms)));
    }
    Ok((lines, ticks))
}

/// The steps of the silhouettes pass that cull and clamp: Lloyd's "time for clamping".
const CLAMPING: [&str; 3] = [
    pass_label::volumes::RECEIVER_GRID,
    pass_label::volumes::CULL_AND_CLAMP,
    pass_label::volumes::BIG_CASTERS,
];

/// The median GPU ms of `row`'s [`CLAMPING`] steps, summed; none where none was timed.
fn clamping_ms(row: &BenchRow) -> Option<f64> {
    let timed: Vec<f64> = row
        .passes
        .iter()
        .filter(|(label, depth, _)| *depth == 1 && CLAMPING.contains(&label.as_str()))
        .map(|(_, _, ms)| *ms)
        .collect();
    (!timed.is_empty()).then(|| timed.iter().sum())
}

/// Draws the figure of `rows` into the PNG `out`.
pub(super) fn plot(
    rows: &[BenchRow],
    baseline: &str,
    title: &str,
    out: &Path,
) -> anyhow::Result<()> {
    let (lines, ticks) = series(rows, baseline)?;
    across(
        &lines,
        &ticks,
        (
            title,
            "slicing planes (K)",
            "GPU ms (medians over the path)",
        ),
        out,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(setting: &str, method: &str, shadow_pass: f64, stencil: f64) -> BenchRow {
        let mut r = super::super::summarise(setting, method, &[]);
        r.shadow_pass_ms = Some(shadow_pass);
        r.passes = vec![
            (pass_label::VOLUME_SILHOUETTES.to_owned(), 0, 5.0),
            (pass_label::volumes::RECEIVER_GRID.to_owned(), 1, 0.5),
            (pass_label::volumes::CULL_AND_CLAMP.to_owned(), 1, 1.0),
        ];
        r.volume_pass_frames = vec![stencil, stencil + 2.0, stencil - 2.0];
        r
    }

    #[test]
    fn the_figure_saves_against_standard_volumes_per_slice_and_method() {
        let rows = [
            row(STANDARD_VOLUMES, "none", 20.0, 14.0),
            row(STANDARD_VOLUMES, "bvol", 12.0, 7.0),
            row("1 slice", "none", 15.0, 9.0),
            row("1 slice", "bvol", 9.0, 4.0),
            row("2 slices", "none", 13.0, 7.0),
            row("2 slices", "bvol", 8.0, 3.0),
        ];
        let (lines, ticks) = series(&rows, "none").unwrap();
        assert_eq!(ticks, ["1 slice", "2 slices"]);
        let labels: Vec<&str> = lines.iter().map(|l| l.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "standard volumes, none: shadow pass",
                "none: stencil pass",
                "none: cull + clamp",
                "none: saved",
                "bvol: stencil pass",
                "bvol: cull + clamp",
                "bvol: saved"
            ]
        );
        assert_eq!(lines[0].values, [Some(20.0), Some(20.0)]);
        assert_eq!(lines[1].values, [Some(9.0), Some(7.0)]);
        assert_eq!(lines[2].values, [Some(1.5), Some(1.5)]);
        assert_eq!(lines[3].values, [Some(5.0), Some(7.0)]);
        assert_eq!(lines[6].values, [Some(11.0), Some(12.0)]);
        // Without standard volumes' time there is nothing to save against.
        assert!(series(&rows[2..], "none").is_err());
        // Clamping may cost more than it saves: a negative saving is drawn too.
        let mut dearer = rows.clone();
        dearer[5].shadow_pass_ms = Some(26.0);
        assert_eq!(
            series(&dearer, "none").unwrap().0[6].values,
            [Some(11.0), Some(-6.0)]
        );
        let out = std::env::temp_dir().join(format!("slices-plot-{}.png", std::process::id()));
        for drawn in [&rows[..], &dearer[..]] {
            plot(drawn, "none", "test", &out).unwrap();
            let image = image::open(&out).unwrap();
            assert_eq!((image.width(), image.height()), crate::plot_png::SIZE);
        }
        let _ = std::fs::remove_file(out);
    }
}
