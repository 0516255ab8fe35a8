//! What the binary's tests share: the binary, a folder per test, and its output as text.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn shadowlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_shadowlab"))
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
