//! The rtlab binary: parse the command line, run, and turn errors into exit status 2.
//! This is the only place that knows about exit codes.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = rtlab::cli::Cli::parse(); // usage errors exit with status 2 from clap
    match rtlab::cli::run(cli, &mut std::io::stdout().lock()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
