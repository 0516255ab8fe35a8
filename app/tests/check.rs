//! `shadowlab check`: the hard cases on a scene, every technique, pass or fail with figures.

mod common;

use common::{run, shadowlab, text};

#[test]
fn check_runs_every_hard_case_with_every_technique_and_passes_on_the_boxes() {
    let output = run(shadowlab().args(["check", "builtin:boxes", "--size", "160x90"]));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}", text(&output));
    let cases = [
        "the scene's view",
        "grazing sun (1°)",
        "sun at the zenith",
        "inside the largest",
        "looking into the sun",
        "a view of nothing",
        "100 km out",
    ];
    let techniques = [
        "single map, frag",
        "single map, dr-conservative",
        "lispsm, vfc",
        "cascades, frag",
        "volumes, standard",
        "volumes, conservative CC",
        "virtual maps",
    ];
    for case in cases {
        for technique in techniques {
            let line = stdout
                .lines()
                .find(|l| l.starts_with(case) && l.contains(technique))
                .unwrap_or_else(|| panic!("no line for {case} / {technique}:\n{stdout}"));
            assert!(line.contains(" pass "), "{line}");
        }
    }
    assert!(
        stdout.contains(&format!(
            "all {} checks passed",
            cases.len() * techniques.len()
        )),
        "{stdout}"
    );
}
