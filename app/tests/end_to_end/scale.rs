//! The city's size (`builtin:city:N`) and `bench --sweep objects`: rows per size whose object
//! counts grow with the blocks, and sizes out of range named.

use crate::common::{out_dir, run, shadowlab, text};

#[test]
fn the_objects_sweep_runs_each_size_of_the_city_and_counts_its_objects() {
    let csv = out_dir("scale").join("objects.csv");
    let output = run(shadowlab()
        .args([
            "bench",
            "--sweep",
            "objects",
            "--city-blocks",
            "2,3",
            "--methods",
            "vfc,frag",
        ])
        .args([
            "--frames",
            "1",
            "--warmup",
            "1",
            "--size",
            "96x64",
            "--no-truth",
            "--csv",
        ])
        .arg(&csv));
    assert!(output.status.success(), "{}", text(&output));
    let table = std::fs::read_to_string(&csv).expect("CSV written");
    let rows: Vec<Vec<&str>> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 4, "two sizes, two methods: {table}");
    let objects = |row: &[&str]| -> u32 {
        row[0]
            .strip_suffix(" objects")
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("setting {:?}", row[0]))
    };
    assert_eq!(objects(&rows[0]), objects(&rows[1]));
    assert!(
        objects(&rows[2]) > objects(&rows[0]),
        "3 x 3 blocks hold more than 2 x 2"
    );
    // Every caster of the city is a caster: the casters column is the object count.
    for row in &rows {
        assert_eq!(
            row[11].parse::<u32>().expect("casters"),
            objects(row),
            "{row:?}"
        );
    }

    let output = run(shadowlab().args(["bench", "--sweep", "objects", "--city-blocks", "99"]));
    assert!(!output.status.success());
    assert!(
        text(&output).contains("--city-blocks: 99 is outside 2 to 64"),
        "{}",
        text(&output)
    );
    let output = run(shadowlab().args(["shot", "builtin:city:1", "--out", "x.png"]));
    assert!(!output.status.success());
    assert!(
        text(&output).contains("builtin:city:N"),
        "{}",
        text(&output)
    );
}
