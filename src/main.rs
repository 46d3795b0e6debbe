//! The sturmray command line: parses the arguments (clap), hands each
//! subcommand to its module of `cli`, and maps the error to the exit code.
//! Exit codes: 0 success, 2 bad input or usage, 1 an internal error.

mod cli;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use sturmray::error::Error;
use sturmray::io::console::note;

use cli::signals::Interrupted;

#[derive(Parser)]
#[command(
    name = "sturmray",
    version,
    about = "Ray tracing meshes and exact analytic surfaces on Embree"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// No doc comments here: clap would take them for the help texts, which are
// on each subcommand's `Args` in its module.
#[derive(Subcommand)]
enum Command {
    Render(cli::render::Args),
    Merge(cli::merge::Args),
    Info(cli::info::Args),
    Explain(cli::explain::Args),
    Trace(cli::trace::Args),
    Roots(cli::roots::Args),
    Bench(cli::bench::Args),
    Accuracy(cli::accuracy::Args),
}

fn main() -> ExitCode {
    // A panic is a bug, caught (in callbacks and backends) and reported as
    // exit 1 with its message: one line on stderr, not a backtrace hint.
    std::panic::set_hook(Box::new(|info| {
        note(format_args!("sturmray: internal error (a bug): {info}"));
    }));
    let cli = Cli::parse();
    // Not for `roots`: subnormal coefficients are ordinary numbers there, and
    // under DAZ even JSON parsing reads them as 0.
    if !matches!(cli.command, Command::Roots(_)) {
        sturmray::accel::ftz::enable_flush_to_zero();
    }
    let result = match cli.command {
        Command::Render(args) => cli::render::run(args),
        Command::Merge(args) => cli::merge::run(args),
        Command::Info(args) => cli::info::run(args),
        Command::Explain(args) => cli::explain::run(args),
        Command::Trace(args) => cli::trace::run(args),
        Command::Roots(args) => cli::roots::run(args),
        Command::Bench(args) => cli::bench::run(args),
        Command::Accuracy(args) => cli::accuracy::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => exit_code(&err),
    }
}

/// Reports a failed command on stderr and gives its exit code.
fn exit_code(err: &anyhow::Error) -> ExitCode {
    // 128 + SIGINT, as shells report a process a Ctrl-C ended; the image and
    // film state so far are written.
    if err.is::<Interrupted>() {
        return ExitCode::from(130);
    }
    // The chain without repeats: an error's own text often includes its source's.
    let mut message = String::new();
    for cause in err.chain() {
        let text = cause.to_string();
        if !message.contains(&text) {
            if !message.is_empty() {
                message += ": ";
            }
            message += &text;
        }
    }
    note(format_args!("sturmray: {message}"));
    let bad_input = err.chain().any(|cause| {
        cause
            .downcast_ref::<Error>()
            .is_some_and(Error::is_bad_input)
    });
    ExitCode::from(if bad_input { 2 } else { 1 })
}
