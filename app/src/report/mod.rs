//! `shadowlab report`: every technique family along one camera path, as a folder a paper or a
//! review can use: `index.html` and `report.md` (the same blocks, `document.rs`), the rows as
//! CSV and JSON, and the plots (`plots.rs`): each row's GPU frame time along the path, and
//! per family speed against error and against undersampling with the Pareto front. Each
//! family's section ends with the sweeps of the papers' figures (`sweeps.rs`, run and drawn by
//! `swept.rs`): a plot per measure across the swept values.
//!
//! The rows are `bench`'s: the same runs (`bench::run_path`, warm-up and settling), the same
//! summaries and the same cells, so a number here is the one `bench` prints for that row.

mod document;
mod families;
mod plots;
mod sweeps;
mod swept;

use std::path::Path;

use anyhow::Context as _;
use indicatif::{ProgressBar, ProgressStyle};
use render_core::frame::FrameReport;
use render_core::scene::SceneFacts;

use crate::bench::{
    BenchRow, COLUMNS, RunOptions, camera_at, format_csv, path_and_lens, row_cells, run_path,
    summarise,
};
use crate::cli::ReportArgs;
use crate::headless::Session;
use document::Block;
use families::Family;
use plots::{Point, Series};
use sweeps::ReportSweep;
use swept::SweptAt;

/// One row of the report: the family it belongs to, `bench`'s summary, and its frames along
/// the path.
#[derive(serde::Serialize)]
struct ReportRow {
    family: &'static str,
    #[serde(flatten)]
    row: BenchRow,
    /// GPU frame time per measured frame, ms.
    gpu_frame_ms_along_path: Vec<Option<f64>>,
    /// On the family's Pareto front of shadow GPU time against error.
    pareto: bool,
    /// Where it sits in a sweep, for a sweep's rows.
    #[serde(skip_serializing_if = "Option::is_none")]
    swept: Option<SweptAt>,
    /// What the last frame's report noted (fallbacks), and each pass that failed.
    #[serde(skip)]
    notes: Vec<String>,
}

/// A screenshot of the view: its family, its file beside the report, what it shows.
struct Picture {
    family: &'static str,
    file: String,
    label: String,
}

pub fn report(args: &ReportArgs) -> anyhow::Result<()> {
    let mut session = Session::open(&args.scene, &args.view)?;
    let base = args.view.settings(&session.scene)?;
    let (path, template) = path_and_lens(&session, args.path.as_deref(), &args.view)?;
    let facts = SceneFacts::from(&session.scene);
    let (families, mut notes) = families::parse(&args.families, !session.scene.lights.is_empty())?;
    let plan: Vec<(Family, Vec<families::Setting>)> = families
        .into_iter()
        .map(|f| (f, f.settings(&base)))
        .collect();
    let pictures_per_family: Vec<Vec<families::Setting>> =
        plan.iter().map(|(f, _)| f.pictures(&base)).collect();
    let lights: Vec<_> = session.scene.lights.iter().map(|l| l.kind).collect();
    let run_families: Vec<Family> = plan.iter().map(|(f, _)| *f).collect();
    let sweeps = sweeps::parse(&args.sweeps, &run_families)?
        .into_iter()
        .map(|sweep| Ok((sweep, sweep.rows(&base, &lights)?)))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let options = RunOptions {
        frames: args.frames.max(1),
        warmup: args.warmup,
        animate: false,
        time: 0.0,
        no_truth: args.no_truth,
        flicker: false,
        moving_sun_deg_per_s: 0.0,
        speed_m_per_s: None,
    };
    let sweep_options = RunOptions {
        frames: args.sweep_frames.max(1),
        ..options
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let adapter = session.ctx.adapter_description();
    let family_rows = plan.iter().map(|(_, s)| s.len()).sum::<usize>();
    let sweep_rows = sweeps.iter().map(|(_, r)| r.len()).sum::<usize>();
    eprintln!(
        "report {}: {family_rows} rows along '{}', {} frames after {} warm-up each, and {sweep_rows} \
         rows of sweeps with {} frames each, on {adapter}",
        facts.name, path.name, options.frames, options.warmup, sweep_options.frames,
    );
    let bar = progress(
        family_rows as u64 * u64::from(options.warmup + options.frames)
            + sweep_rows as u64 * u64::from(sweep_options.warmup + sweep_options.frames),
    );
    let mut rows: Vec<ReportRow> = Vec::new();
    let mut pictures: Vec<Picture> = Vec::new();
    // The screenshots show the view the command names (`--eye`), else the path's middle.
    let shown_view = if args.view.eye.is_some() {
        template
    } else {
        camera_at(
            &path,
            &template,
            (options.warmup + options.frames / 2, &options),
        )
    };
    for ((family, settings), shown) in plan.iter().zip(&pictures_per_family) {
        let first = rows.len();
        for setting in settings {
            bar.set_message(format!("{}: {}", family.name(), setting.label));
            let reports = run_path(
                &mut session,
                (&path, &template),
                &setting.settings,
                &options,
                &mut |_| bar.inc(1),
            )?;
            if bar.is_hidden() {
                eprintln!("  {}: {} done", family.name(), setting.label);
            }
            rows.push(row(
                *family,
                &setting.label,
                setting.settings.method.name(),
                &reports,
            ));
        }
        compare_within(&mut rows[first..]);
        for (k, picture) in shown.iter().enumerate() {
            bar.set_message(format!("{}: screenshot {}", family.name(), k + 1));
            let file = format!("{}-view-{}.png", family.name(), k + 1);
            let image = session.picture(&shown_view, &picture.settings)?;
            crate::headless::write_png(&image, &args.out.join(&file))?;
            pictures.push(Picture {
                family: family.name(),
                file,
                label: picture.label.clone(),
            });
        }
        for (sweep, sweep_rows) in sweeps.iter().filter(|(s, _)| s.family() == *family) {
            rows.extend(swept::run(
                &mut session,
                (&path, &template),
                (*sweep, sweep_rows),
                &sweep_options,
                &bar,
            )?);
        }
    }
    bar.finish_and_clear();
    notes.extend(grouped_notes(&rows));
    write(
        &args.out,
        (&rows, &pictures),
        (&facts, &adapter, &path.name, &options),
        &notes,
    )?;
    eprintln!("wrote {}", args.out.join("index.html").display());
    Ok(())
}

fn progress(frames: u64) -> ProgressBar {
    let bar = ProgressBar::new(frames);
    if let Ok(style) = ProgressStyle::with_template(
        "{msg:32} [{bar:30}] {pos}/{len} frames, {elapsed} so far, about {eta} left",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

fn row(family: Family, label: &str, method: &str, reports: &[(f64, FrameReport)]) -> ReportRow {
    // The last frame's notes (a fallback holds every frame; figures in notes change from
    // frame to frame), and every failed pass once.
    let mut notes: Vec<String> = reports
        .last()
        .map(|(_, r)| r.notes.clone())
        .unwrap_or_default();
    for failure in reports
        .iter()
        .filter_map(|(_, r)| r.shadow_failure.as_ref())
    {
        if !notes.contains(failure) {
            notes.push(failure.clone());
        }
    }
    ReportRow {
        notes,
        family: family.name(),
        row: summarise(label, method, reports),
        gpu_frame_ms_along_path: reports.iter().map(|(_, r)| r.gpu_total_ms()).collect(),
        pareto: false,
        swept: None,
    }
}

/// Speed-ups against the family's first row, the fill saved against it (shadow volumes), and
/// the Pareto front.
fn compare_within(rows: &mut [ReportRow]) {
    speed_ups_against_first(rows);
    let summaries: Vec<&BenchRow> = rows.iter().map(|r| &r.row).collect();
    let (indices, points) = error_points(&summaries);
    for i in plots::pareto_front(&points) {
        rows[indices[i]].pareto = true;
    }
}

/// Speed-ups against the first row, and the fill and stencil time saved against it.
fn speed_ups_against_first(rows: &mut [ReportRow]) {
    let Some(first) = rows.first().map(|r| r.row.clone()) else {
        return;
    };
    let mut summaries: Vec<BenchRow> = rows.iter().map(|r| r.row.clone()).collect();
    crate::bench::set_fill_saved(&mut summaries, &first.method);
    for (r, summary) in rows.iter_mut().zip(summaries) {
        r.row = summary;
        r.row.speed_up = first
            .gpu_frame_ms
            .zip(r.row.gpu_frame_ms)
            .map(|(b, m)| b / m.max(1e-9));
    }
}

/// Each row's shadow GPU time (its shadow passes and its culling) and its error: against the
/// exact shadow where it was measured, else against the reference maps. The rows that have
/// both, by index.
fn error_points(rows: &[&BenchRow]) -> (Vec<usize>, Vec<Point>) {
    let exact = against_truth(rows);
    rows.iter()
        .enumerate()
        .filter_map(|(i, r)| {
            let y = if exact {
                r.exact_error.0?
            } else {
                f64::from(r.error_px_max)
            };
            Some((i, point(r, shadow_gpu_ms(r)?, y)))
        })
        .unzip()
}

/// Whether every row was measured against the exact shadow.
fn against_truth(rows: &[&BenchRow]) -> bool {
    rows.iter().all(|r| r.exact_error.0.is_some())
}

/// The shadow passes' and the culling's GPU time.
fn shadow_gpu_ms(row: &BenchRow) -> Option<f64> {
    Some(row.shadow_pass_ms? + row.culling_ms.unwrap_or(0.0))
}

fn point(row: &BenchRow, x: f64, y: f64) -> Point {
    Point {
        label: if row.setting == row.method {
            row.method.clone()
        } else {
            row.setting.clone()
        },
        x,
        y,
    }
}

/// What a reader needs to know of the rows that the tables do not say: their frames' notes
/// (fallbacks, failed passes) and a missing GPU time, each note once with the rows it holds
/// for.
fn grouped_notes(rows: &[ReportRow]) -> Vec<String> {
    let mut grouped: Vec<(&str, Vec<String>)> = Vec::new();
    for r in rows {
        let no_time = r.row.shadow_pass_ms.is_none().then_some(
            "this adapter gave no GPU time for the shadow passes, so the row is not in the \
             speed plots",
        );
        for note in r.notes.iter().map(String::as_str).chain(no_time) {
            let name = format!("{} / {}", r.family, r.row.setting);
            match grouped.iter_mut().find(|(n, _)| *n == note) {
                Some((_, names)) => names.push(name),
                None => grouped.push((note, vec![name])),
            }
        }
    }
    grouped
        .into_iter()
        .map(|(note, names)| format!("{}: {note}", names.join(", ")))
        .collect()
}

/// The columns of `bench`'s table the report shows, by index into [`COLUMNS`].
const SHOWN: [usize; 13] = [0, 1, 4, 5, 6, 8, 9, 12, 13, 14, 17, 18, 21];

/// Writes the folder: rows as CSV and JSON, the plots, `report.md` and `index.html`.
fn write(
    out: &Path,
    (rows, pictures): (&[ReportRow], &[Picture]),
    (facts, adapter, path_name, options): (&SceneFacts, &str, &str, &RunOptions),
    notes: &[String],
) -> anyhow::Result<()> {
    let write_file = |name: &str, text: &str| {
        let file = out.join(name);
        std::fs::write(&file, text).with_context(|| format!("writing {}", file.display()))
    };
    let summaries: Vec<BenchRow> = rows
        .iter()
        .map(|r| BenchRow {
            setting: match &r.swept {
                Some(at) => format!("{} sweep: {}", at.sweep, r.row.setting),
                None => format!("{}: {}", r.family, r.row.setting),
            },
            ..r.row.clone()
        })
        .collect();
    write_file("rows.csv", &format_csv(&summaries))?;
    write_file("rows.json", &serde_json::to_string_pretty(rows)?)?;
    let command: Vec<String> = std::env::args().skip(1).collect();
    let mut blocks = vec![
        Block::Heading(1, format!("shadowlab report: {}", facts.name)),
        Block::Paragraph(format!(
            "Adapter: {adapter}. Absolute times are this adapter's own: compare rows by their \
             ratios within this run, not with another machine's."
        )),
        Block::Paragraph(format!(
            "Scene: {} objects ({} casters), {} triangles. Path '{path_name}', {} measured \
             frames after {} warm-up for every row; each frame is rendered once timed and once \
             measured (error, oracle, undersampling, and the exact shadow where it applies).",
            facts.objects, facts.casters, facts.triangles, options.frames, options.warmup,
        )),
        Block::Paragraph(format!("Command: `shadowlab {}`", command.join(" "))),
    ];
    if let Some(swept) = rows.iter().find(|r| r.swept.is_some()) {
        blocks.push(Block::Paragraph(format!(
            "The sweeps (each in its family's section) vary one setting of the papers' figures \
             over the same path, {} measured frames after {} warm-up for each of their rows.",
            swept.row.frames, options.warmup
        )));
    }
    for note in notes {
        blocks.push(Block::Paragraph(format!("Note: {note}")));
    }
    let mut families: Vec<&'static str> = rows.iter().map(|r| r.family).collect();
    families.dedup();
    for family in families {
        let of_family: Vec<&ReportRow> = rows
            .iter()
            .filter(|r| r.family == family && r.swept.is_none())
            .collect();
        family_blocks(out, family, &of_family, &mut blocks)?;
        for picture in pictures.iter().filter(|p| p.family == family) {
            blocks.push(Block::Paragraph(format!("The view, {}:", picture.label)));
            blocks.push(Block::Image(picture.file.clone(), picture.label.clone()));
        }
        for sweep in ReportSweep::ALL {
            let of_sweep: Vec<&ReportRow> = rows
                .iter()
                .filter(|r| r.swept.as_ref().is_some_and(|at| at.sweep == sweep.name()))
                .collect();
            if sweep.family().name() == family && !of_sweep.is_empty() {
                swept::blocks(out, sweep, &of_sweep, &mut blocks);
            }
        }
    }
    blocks.push(Block::Heading(2, "Files".into()));
    blocks.push(Block::Paragraph(
        "`rows.csv` holds every row as `bench --csv` writes it (the setting is `family: \
         setting`); `rows.json` the same with each row's GPU frame time along the path."
            .into(),
    ));
    write_file("report.md", &document::markdown(&blocks))?;
    write_file(
        "index.html",
        &document::html(&format!("shadowlab report: {}", facts.name), &blocks),
    )
}

/// The rows' table: `bench`'s columns the report shows, and with `pareto` whether each row
/// is on the Pareto front.
fn table(rows: &[&ReportRow], pareto: bool) -> Block {
    let mut header: Vec<String> = SHOWN.iter().map(|&c| COLUMNS[c].to_owned()).collect();
    header[SHOWN.len() - 1] = format!("speed-up vs {}", rows[0].row.setting);
    if pareto {
        header.push("Pareto".into());
    }
    let table = rows
        .iter()
        .map(|r| {
            let cells = row_cells(&r.row);
            let mut shown: Vec<String> = SHOWN.iter().map(|&c| cells[c].clone()).collect();
            if pareto {
                shown.push(if r.pareto { "yes" } else { "" }.to_owned());
            }
            shown
        })
        .collect();
    Block::Table(header, table)
}

/// A family's section: its table and plots.
fn family_blocks(
    out: &Path,
    family: &str,
    rows: &[&ReportRow],
    blocks: &mut Vec<Block>,
) -> anyhow::Result<()> {
    let described = Family::named(family).map_or("", Family::description);
    blocks.push(Block::Heading(
        2,
        described.split(':').next().unwrap_or(family).into(),
    ));
    blocks.push(Block::Paragraph(described.into()));
    blocks.push(table(rows, true));
    let series: Vec<Series> = rows
        .iter()
        .map(|r| Series {
            label: r.row.setting.clone(),
            values: r.gpu_frame_ms_along_path.clone(),
        })
        .collect();
    let along = format!("{family}-along-path.png");
    plots::along_path(
        &series,
        (
            &format!("{family}: GPU frame time along the path"),
            "GPU frame ms",
        ),
        &out.join(&along),
    )?;
    blocks.push(Block::Image(
        along,
        format!("{family}: GPU frame time along the path"),
    ));
    let summaries: Vec<&BenchRow> = rows.iter().map(|r| &r.row).collect();
    let (_, points) = error_points(&summaries);
    if !points.is_empty() {
        let y_label = if against_truth(&summaries) {
            "error px against the exact shadow (median)"
        } else {
            "error px against the reference (worst frame)"
        };
        let file = format!("{family}-speed-error.png");
        let title = format!("{family}: shadow GPU time against error");
        plots::speed_against(
            &points,
            (&title, "shadow passes + culling, GPU ms", y_label),
            &out.join(&file),
        )?;
        blocks.push(Block::Image(file, title));
    }
    let undersampled: Vec<Point> = summaries
        .iter()
        .filter_map(|r| Some(point(r, shadow_gpu_ms(r)?, r.undersampling.1?)))
        .collect();
    if !undersampled.is_empty() {
        let file = format!("{family}-speed-undersampling.png");
        let title = format!("{family}: shadow GPU time against undersampling");
        plots::speed_against(
            &undersampled,
            (
                &title,
                "shadow passes + culling, GPU ms",
                "undersampling p95, octaves",
            ),
            &out.join(&file),
        )?;
        blocks.push(Block::Image(file, title));
    }
    Ok(())
}
