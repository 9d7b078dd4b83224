//! `seamlit`: fix, inspect, render, compare and view multi-object models with seam-free
//! per-pixel lighting. `seamlit --help` lists the subcommands; docs/design.md section 8 is the
//! design. Exit status: 0 success, 1 processing failure, 2 bad input or usage.

mod animate;
// The two-object character of the animation tests, for the unit tests here.
#[cfg(test)]
use seamlit_testkit::character;
mod cli;
mod cmd;
mod draw;
mod failure;
mod motion;
mod output;
mod picture;
mod prepare;
mod table;
mod view;

use std::process::ExitCode;

use clap::Parser;

use crate::cli::{Cli, Command};

fn main() -> ExitCode {
    // clap exits with status 2 on a usage error, 0 for --help and --version.
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Demo(args) => cmd::demo::run(args),
        Command::Fix(args) => cmd::fix::run(args),
        Command::Inspect(args) => cmd::inspect::run(args),
        Command::Render(args) => cmd::render::run(args),
        Command::Compare(args) => cmd::compare::run(args),
        Command::View(args) => view::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("error: {failure}");
            failure.exit_code()
        }
    }
}
