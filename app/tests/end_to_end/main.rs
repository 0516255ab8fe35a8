//! The end-to-end tier: tests that run the `shadowlab` binary (the CLI contract, its exit
//! codes and files, the window under Xvfb), one module per subject in one test binary.

mod cascades;
mod check;
mod cli;
mod common;
mod faults;
mod lights;
mod pictures;
mod remembered;
mod report;
mod scale;
mod window_loading;
