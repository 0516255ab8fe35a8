//! What the binary's tests share: the binary, a folder per test, and its output as text.

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

pub fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}
