//! `sim`: see `railsim::cli`.

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    preproc::cli::exit_quietly_on_closed_pipe();
    let cli = railsim::cli::Cli::parse();
    match railsim::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let interrupted = e.downcast_ref::<railsim::cli::Interrupted>().is_some();
            let messages = railsim::error_text::chain_messages(&e);
            for (i, m) in messages.iter().enumerate() {
                if i == 0 {
                    eprintln!("error: {m}");
                } else {
                    eprintln!("  caused by: {m}");
                }
            }
            if interrupted {
                ExitCode::from(railsim::cli::INTERRUPTED_EXIT_CODE)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}
