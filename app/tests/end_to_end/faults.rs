//! GPU faults, as a user meets them: a window whose device is lost opens a new one and shows
//! the same view; a minimised window draws nothing and then the same view; maps the GPU cannot
//! hold are named, in the window (which keeps running on the settings it had) and by `shot`
//! (which exits non-zero). Never a wgpu panic.

use crate::common::{has_display, out_dir, run, run_window, screenshot_stats, shadowlab, text};

/// The hall's 32 lights with maps of 4096: 4.5 GiB, more than lavapipe gives one texture.
const TOO_MUCH: [&str; 5] = ["builtin:hall", "--shadow", "lights", "--shadow-res", "4096"];

/// The window on the boxes under cascades with their overlay, through `drill`: its output.
fn drilled(drill: &str) -> String {
    let shots = out_dir(&format!("fault-drill-{drill}"));
    let output = run_window(
        shadowlab()
            .args([
                "builtin:boxes",
                "--fresh",
                "--shadow",
                "cascades",
                "--overlay",
                "cascades",
                "--exit-after-frames",
                "6",
                "--fault-drill",
                drill,
                "--screenshot-dir",
            ])
            .arg(&shots),
    );
    let all = text(&output);
    assert!(output.status.success(), "{drill}: {all}");
    assert!(!all.contains("panicked"), "{drill}: {all}");
    let stats = screenshot_stats(&shots);
    assert_eq!(
        stats["technique"], "cascades",
        "{drill}: the settings are kept"
    );
    all
}

#[test]
fn a_window_whose_device_is_lost_opens_a_new_one_and_shows_the_same_view() {
    if !has_display() {
        return;
    }
    let all = drilled("device-lost");
    assert!(
        all.contains("the GPU device was lost (destroyed)")
            && all.contains("opened a new device on"),
        "{all}"
    );
    assert!(
        all.contains("differs from the view before in 0 pixels"),
        "{all}"
    );
}

#[test]
fn a_minimised_window_draws_nothing_and_then_the_same_view() {
    if !has_display() {
        return;
    }
    let all = drilled("minimised");
    assert!(
        all.contains("fault drill Minimised: the fault is on"),
        "{all}"
    );
    assert!(
        all.contains("differs from the view before in 0 pixels"),
        "{all}"
    );
}

#[test]
fn a_window_asked_for_maps_the_gpu_cannot_hold_says_so_and_keeps_running() {
    if !has_display() {
        return;
    }
    let shots = out_dir("fault-memory-window");
    let output = run_window(
        shadowlab()
            .args(TOO_MUCH)
            .args(["--fresh", "--exit-after-frames", "3", "--screenshot-dir"])
            .arg(&shots),
    );
    let all = text(&output);
    assert!(output.status.success(), "{all}");
    assert!(!all.contains("panicked"), "{all}");
    assert!(
        all.contains("GPU memory exhausted: the many lights' maps")
            && all.contains("4096 x 4096")
            && all.contains("The default settings are back"),
        "{all}"
    );
    // The screenshot after it is of a frame that drew, with the settings the window fell
    // back to.
    let stats = screenshot_stats(&shots);
    assert_eq!(stats["technique"], "single", "{stats}");
}

#[test]
fn shot_names_maps_the_gpu_cannot_hold_and_a_lost_device_and_exits_non_zero() {
    let dir = out_dir("fault-shot");
    let memory = run(shadowlab()
        .arg("shot")
        .args(TOO_MUCH)
        .args(["--size", "160x90", "--out"])
        .arg(dir.join("memory.png")));
    let all = text(&memory);
    assert_eq!(memory.status.code(), Some(1), "{all}");
    assert!(
        all.contains("GPU memory exhausted: the many lights' maps")
            && all.contains("asked for 4.5 GiB")
            && all.contains("--shadow-res"),
        "{all}"
    );
    let lost = run(shadowlab()
        .args(["shot", "builtin:boxes", "--size", "160x90", "--no-truth"])
        .args(["--fault-drill", "device-lost", "--out"])
        .arg(dir.join("lost.png")));
    let all = text(&lost);
    assert_eq!(lost.status.code(), Some(1), "{all}");
    assert!(all.contains("the GPU device was lost"), "{all}");
    assert!(!all.contains("panicked"), "{all}");
}
