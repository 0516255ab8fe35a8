//! What the binary's tests share: the binary, a folder per test, its output as text, and for
//! the window tests whether there is a display and the stats of the screenshot it saved.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary, with a config folder of its own (the window remembers its settings there, not
/// in the user's): a fresh folder per command, so no run reads another's settings.
pub fn shadowlab() -> Command {
    use std::sync::atomic::{AtomicU32, Ordering};
    static RUNS: AtomicU32 = AtomicU32::new(0);
    let config = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "config-{}-{}",
        std::process::id(),
        RUNS.fetch_add(1, Ordering::Relaxed)
    ));
    let mut command = Command::new(env!("CARGO_BIN_EXE_shadowlab"));
    command.env("SHADOWLAB_CONFIG_DIR", config);
    command
}

pub fn out_dir(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(test);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

pub fn run(cmd: &mut Command) -> Output {
    cmd.output().expect("shadowlab runs")
}

/// One window at a time in a test binary: the window tests of a file run as threads, and a
/// window that opens while another sets up its surface has failed to reach the X server
/// under `xvfb-run` once. Hold the guard while a window is open.
pub fn window_lock() -> std::sync::MutexGuard<'static, ()> {
    static WINDOW: std::sync::Mutex<()> = std::sync::Mutex::new(());
    WINDOW
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Runs a command that opens the window, one window at a time; when it could not reach the
/// display server at all (the virtual display's fault, not the window's), once more.
pub fn run_window(cmd: &mut Command) -> Output {
    let _window = window_lock();
    let output = run(cmd);
    if !output.status.success() && text(&output).contains("Failed to open connection to X server") {
        eprintln!("the display server refused the window; trying once more");
        std::thread::sleep(std::time::Duration::from_secs(1));
        return run(cmd);
    }
    output
}

pub fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

/// Whether the window tests can open a window. Without a display they are skipped, but not
/// in CI, which must run them under one (`xvfb-run`).
pub fn has_display() -> bool {
    let has =
        std::env::var_os("DISPLAY").is_some() || std::env::var_os("WAYLAND_DISPLAY").is_some();
    if !has {
        assert!(
            std::env::var("CI").is_err(),
            "CI must run the window tests under a display (xvfb-run)"
        );
        eprintln!("window test skipped: no display; `scripts/test.sh` gets one from xvfb-run");
    }
    has
}

/// The stats JSON of the screenshot the window saved into `folder` (`--screenshot-dir`).
pub fn screenshot_stats(folder: &Path) -> serde_json::Value {
    let json = std::fs::read_dir(folder)
        .expect("screenshot folder")
        .flatten()
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|e| e == "json"))
        .expect("the window saved a screenshot and its stats");
    serde_json::from_str(&std::fs::read_to_string(json).expect("stats")).expect("JSON")
}
