//! `shadowlab`: the window (winit + egui) and the headless command line, over one frame code.

mod bench;
mod check;
mod cli;
mod headless;
mod legend_image;
mod plot_png;
mod report;
mod scene_source;
mod window;

use std::process::ExitCode;

use clap::Parser as _;

fn main() -> ExitCode {
    env_logger::Builder::from_env(
        env_logger::Env::default().default_filter_or("warn,shadowlab=info"),
    )
    .init();
    let cli = cli::Cli::parse();
    let result = match &cli.command {
        Some(cli::Command::Shot(args)) => headless::shot(args),
        Some(cli::Command::Bench(args)) => bench::bench(args),
        Some(cli::Command::Report(args)) => report::report(args),
        Some(cli::Command::Check(args)) => check::check(args),
        Some(cli::Command::Scenes) => {
            headless::list_scenes();
            Ok(())
        }
        None => window::run(&cli.open),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("shadowlab: {e:#}");
            ExitCode::FAILURE
        }
    }
}
