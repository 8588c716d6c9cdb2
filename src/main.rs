//! The rtlab binary: parse the command line, run, and turn errors into exit status 2 (and
//! `diff`'s "the images differ" into 1). This is the only place that knows about exit codes.

use clap::Parser;
use std::process::ExitCode;

/// mimalloc rather than the system's allocator: memory a render frees is kept for the next
/// one in the same process (progressive passes, `rtlab serve`) instead of being handed back
/// to the kernel and faulted in again page by page (Cargo.toml says how much that cost).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    rtlab::interrupt::install();
    let cli = match rtlab::cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind::{
                DisplayHelp, DisplayHelpOnMissingArgumentOrSubcommand, DisplayVersion,
            };
            match e.kind() {
                // --help and --version (status 0), or the help for a bare `rtlab`: clap's own.
                DisplayHelp | DisplayVersion | DisplayHelpOnMissingArgumentOrSubcommand => e.exit(),
                // A bad command line: one line, as every other bad input.
                _ => {
                    let words: Vec<String> = std::env::args_os()
                        .skip(1)
                        .map(|a| a.to_string_lossy().into_owned())
                        .collect();
                    let command = <rtlab::cli::Cli as clap::CommandFactory>::command();
                    let line = rtlab::cli::usage_line_in(&e, &command, &words);
                    eprintln!("error: {}", rtlab::error::printable(&line));
                    return ExitCode::from(2);
                }
            }
        }
    };
    if let Err(v) = rtlab::accel::isa::simd_cap() {
        eprintln!(
            "warning: RTLAB_SIMD={} names no SIMD level (base or portable, avx2, avx512): ignored, the widest this processor has is used",
            rtlab::error::printable(&v)
        );
    }
    match rtlab::cli::run_outcome(cli, &mut std::io::stdout().lock()) {
        Ok(rtlab::cli::Outcome::Same) => ExitCode::SUCCESS,
        Ok(rtlab::cli::Outcome::Different) => ExitCode::from(1),
        // `rtlab explain … | head`: the reader took what it wanted; as `cat` and `grep` do
        // when their output closes, stop without a word.
        Err(rtlab::error::Error::OutputClosed) => ExitCode::SUCCESS,
        // Ctrl-C: 128 + SIGINT, what a shell reports for a program the signal stopped.
        Err(e) if rtlab::interrupt::requested() => {
            eprintln!("error: {}", rtlab::error::printable(&e.to_string()));
            ExitCode::from(130)
        }
        Err(e) => {
            eprintln!("error: {}", rtlab::error::printable(&e.to_string()));
            ExitCode::from(2)
        }
    }
}
