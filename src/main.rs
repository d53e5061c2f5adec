//! The `penumbra` command line: render a scene file (or the built-in default scene) to an
//! image, or tell how an image was made. Argument handling lives in `cli/`.

mod cli;

use std::process::ExitCode;

use clap::Parser;

use cli::{Cli, Command};

fn main() -> ExitCode {
    let argv: Vec<String> = std::env::args().collect();
    let result = match Cli::parse_from(&argv).command {
        Some(Command::Render(args)) => cli::render::run(&args, &cli::meta::replay_tokens(&argv)),
        None => cli::render::run(&cli::render::RenderArgs::default_scene(), &[]),
        Some(Command::Info(args)) => cli::info::run(&args),
        Some(Command::Animate(args)) => cli::animate::run(&args, &argv),
        Some(Command::Sweep(args)) => cli::sweep::run(&args),
        Some(Command::Status(args)) => cli::status::run(&args),
        Some(Command::Report(args)) => cli::report::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", cli::error_line(&e));
            cli::exit_code(&e)
        }
    }
}
