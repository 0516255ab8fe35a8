//! `shadowlab check`: the hard cases on a scene, every technique, pass or fail with figures.
//! On the house of `assets/scenes/house.gltf` (a closed house of one mesh, cut into chunks as
//! any glTF is), whose zenith case once failed at this size; the case inside it fails only
//! at 1280x720, which `tests/tests/gpu/check_cases.rs` renders.

use crate::common::{run, shadowlab, text};

#[test]
fn check_runs_every_hard_case_with_every_technique_and_passes_on_the_house() {
    let house = concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/scenes/house.gltf");
    let output =
        run(shadowlab().args(["check", house, "--sun", "0.5,0.8,0.3", "--size", "640x360"]));
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
        // Each case first names its view as `shot` flags.
        assert!(
            stdout
                .lines()
                .any(|l| l.starts_with(&format!("{case}: --eye ")) && l.contains(" --sun ")),
            "no view for {case}:\n{stdout}"
        );
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
