//! The bench's printed table, its CSV and the per-pass table.

use std::fmt::Write as _;

use super::BenchRow;

/// One column per method (and setting), one row per pass label; steps indented under their pass.
pub(super) fn format_passes(rows: &[BenchRow]) -> String {
    let mut labels: Vec<(&str, u32)> = Vec::new();
    for (label, depth, _) in rows.iter().flat_map(|r| &r.passes) {
        if !labels.contains(&(label.as_str(), *depth)) {
            labels.push((label, *depth));
        }
    }
    let header = std::iter::once("pass".to_owned()).chain(rows.iter().map(|r| {
        if r.setting.is_empty() {
            r.method.clone()
        } else {
            format!("{} {}", r.setting, r.method)
        }
    }));
    let lines: Vec<Vec<String>> = std::iter::once(header.collect())
        .chain(labels.iter().map(|&(label, depth)| {
            let name = format!("{}{label}", "  ".repeat(depth as usize));
            std::iter::once(name)
                .chain(rows.iter().map(|r| {
                    r.passes
                        .iter()
                        .find(|(l, d, _)| l == label && *d == depth)
                        .map_or_else(|| "-".into(), |(_, _, ms)| format!("{ms:.2}"))
                }))
                .collect()
        }))
        .collect();
    aligned(&lines, 1)
}

pub(crate) const COLUMNS: [&str; 28] = [
    "setting",
    "method",
    "frames",
    "frame ms",
    "GPU frame ms",
    "shadow pass ms",
    "mask+cull ms",
    "CPU cull ms",
    "casters drawn",
    "oracle",
    "tightness",
    "shadow triangles",
    "error px (max)",
    "exact err px median (off edges)",
    "exact err %",
    "flicker move/turn",
    "under p50",
    "under p95",
    "fill M (max)",
    "fill saved mean/peak",
    "volume pass saved mean/peak",
    "speed-up",
    "pages_marked",
    "pages_resident",
    "pages_rendered",
    "pages_refused",
    "pages_refreshed",
    "cache hits",
];

pub(crate) fn row_cells(r: &BenchRow) -> [String; 28] {
    let opt =
        |v: Option<f64>, digits: usize| v.map_or_else(|| "n/a".into(), |v| format!("{v:.digits$}"));
    [
        r.setting.clone(),
        r.method.clone(),
        r.frames.to_string(),
        format!("{:.2}", r.frame_ms),
        opt(r.gpu_frame_ms, 2),
        opt(r.shadow_pass_ms, 2),
        r.culling_ms
            .map_or_else(|| "-".into(), |v| format!("{v:.2}")),
        opt(r.cpu_culling_ms, 2),
        format!("{:.0}", r.casters_drawn),
        format!("{:.0}", r.casters_oracle),
        opt(r.tightness, 2),
        format!("{:.0}", r.shadow_triangles),
        r.error_px_max.to_string(),
        match (r.exact_error.0, r.exact_off_edge_px) {
            (Some(px), Some(off)) => format!("{px:.0} ({off:.0})"),
            (px, _) => opt(px, 0),
        },
        opt(r.exact_error.1, 2),
        r.flicker
            .map_or_else(|| "-".into(), |(m, t)| format!("{m}/{t}")),
        opt(r.undersampling.0, 2),
        opt(r.undersampling.1, 2),
        match r.fill_m {
            (Some(median), Some(max)) => format!("{median:.1} ({max:.1})"),
            _ => "-".into(),
        },
        saved_cell(r.fill_saved),
        saved_cell(r.volume_pass_saved),
        opt(r.speed_up, 2),
        page_cell(r.pages, 0),
        page_cell(r.pages, 1),
        page_cell(r.pages, 2),
        page_cell(r.pages, 3),
        page_cell(r.pages, 6),
        r.cache_hit_rate
            .map_or_else(|| "-".into(), |v| format!("{:.0}%", 100.0 * v)),
    ]
}

/// Column `i` of the virtual maps' page medians, `-` for other techniques.
fn page_cell(pages: Option<[f64; 11]>, i: usize) -> String {
    pages.map_or_else(|| "-".into(), |p| format!("{:.0}", p[i]))
}

/// A mean and peak ratio, `3.1x/7.0x`.
fn saved_cell(saved: Option<(f64, f64)>) -> String {
    saved.map_or_else(
        || "-".into(),
        |(mean, peak)| format!("{mean:.1}x/{peak:.1}x"),
    )
}

/// An aligned table; the setting column only when sweeping. Speed-up is against `baseline`.
pub(super) fn format_table(rows: &[BenchRow], baseline: &str) -> String {
    let skip = usize::from(rows.iter().all(|r| r.setting.is_empty()));
    let mut header = COLUMNS.map(str::to_owned);
    header[21] = format!("speed-up vs {baseline}");
    let lines: Vec<Vec<String>> = std::iter::once(header.to_vec())
        .chain(rows.iter().map(|r| row_cells(r).to_vec()))
        .map(|l| l[skip..].to_vec())
        .collect();
    aligned(&lines, 2 - skip)
}

/// The cells padded to their column's width: the first `left` columns left-aligned, the
/// others right-aligned.
pub(super) fn aligned(lines: &[Vec<String>], left: usize) -> String {
    let widths: Vec<usize> = (0..lines[0].len())
        .map(|c| {
            lines
                .iter()
                .map(|l| l[c].chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut out = String::new();
    for line in lines {
        let padded: Vec<String> = line
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(c, (cell, &w))| {
                let pad = " ".repeat(w - cell.chars().count());
                if c < left {
                    format!("{cell}{pad}")
                } else {
                    format!("{pad}{cell}")
                }
            })
            .collect();
        let _ = writeln!(out, "{}", padded.join("  ").trim_end());
    }
    out
}

/// A text field of a CSV row: quoted (quotes doubled) where it holds a comma, a quote or a
/// line break (RFC 4180).
fn csv_text(text: &str) -> std::borrow::Cow<'_, str> {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\"")).into()
    } else {
        text.into()
    }
}

pub(crate) fn format_csv(rows: &[BenchRow]) -> String {
    let mut out = String::from(
        "setting,method,frames,frame_ms,gpu_frame_ms,shadow_pass_ms,casters_drawn,casters_oracle,tightness,shadow_triangles,error_px_max,casters_total,speed_up,culling_ms,undersampling_p50,undersampling_p95,exact_error_px,exact_error_percent,exact_error_off_edge_px_max,flicker_moved_px,flicker_turned_px,fill_mfragments,fill_mfragments_max,fill_saved_mean,fill_saved_peak,volume_pass_saved_mean,volume_pass_saved_peak,cpu_culling_ms,pages_marked,pages_resident,pages_rendered,pages_refused,texels_rendered,texels_sampled,pages_refreshed,cull_pages_spanned,cull_flag_reads,moved_pages_occluded,caster_pages_occluded,cache_hit_rate,exact_error_off_edge_px\n",
    );
    let opt = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v:.4}"));
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{:.4},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            csv_text(&r.setting),
            csv_text(&r.method),
            r.frames,
            r.frame_ms,
            opt(r.gpu_frame_ms),
            opt(r.shadow_pass_ms),
            r.casters_drawn,
            r.casters_oracle,
            opt(r.tightness),
            r.shadow_triangles,
            r.error_px_max,
            r.casters_total,
            opt(r.speed_up),
            opt(r.culling_ms),
            opt(r.undersampling.0),
            opt(r.undersampling.1),
            opt(r.exact_error.0),
            opt(r.exact_error.1),
            r.exact_off_edge_px_max
                .map_or_else(String::new, |v| v.to_string()),
            r.flicker.map_or_else(String::new, |f| f.0.to_string()),
            r.flicker.map_or_else(String::new, |f| f.1.to_string()),
            opt(r.fill_m.0),
            opt(r.fill_m.1),
            opt(r.fill_saved.map(|f| f.0)),
            opt(r.fill_saved.map(|f| f.1)),
            opt(r.volume_pass_saved.map(|f| f.0)),
            opt(r.volume_pass_saved.map(|f| f.1)),
            opt(r.cpu_culling_ms),
            r.pages.map_or_else(
                || ",,,,,,,,,,".to_owned(),
                |p| p.map(|v| format!("{v:.0}")).join(",")
            ),
            opt(r.cache_hit_rate),
            opt(r.exact_off_edge_px),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::csv_text;

    #[test]
    fn a_csv_field_with_a_comma_or_a_quote_is_quoted() {
        assert_eq!(csv_text("virtual / cache off"), "virtual / cache off");
        assert_eq!(csv_text("a, b"), "\"a, b\"");
        assert_eq!(csv_text("say \"x\""), "\"say \"\"x\"\"\"");
    }
}
