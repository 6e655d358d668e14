//! `track-preproc`: see `preproc::cli`.

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    preproc::cli::exit_quietly_on_closed_pipe();
    let cli = preproc::cli::Cli::parse();
    // A build cannot stop half-way with a usable table: the first signal
    // removes the temporary being written and exits with 130.
    let _ = preproc::cli::stop_on_signal(true);
    match preproc::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // A cause the message before it already ends with is not
            // repeated (the library errors carry theirs in both places; see
            // railsim::error_text).
            let mut previous = e.to_string();
            eprintln!("error: {previous}");
            for cause in e.chain().skip(1) {
                let text = cause.to_string();
                if !previous.ends_with(&text) {
                    eprintln!("  caused by: {text}");
                }
                previous = text;
            }
            ExitCode::FAILURE
        }
    }
}
