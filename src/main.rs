//! `tetrasim` command line: parses arguments and hands them to [`tetrasim::cli::execute`].

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = tetrasim::cli::Cli::parse();
    match tetrasim::cli::execute(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            // A diverged run exits with 3 (docs/STABILITY.md); other failures with 1.
            let diverged = e.downcast_ref::<tetrasim::cli::DivergedRun>().is_some()
                || matches!(e.downcast_ref(), Some(tetrasim::Error::Diverged(_)));
            if diverged {
                std::process::ExitCode::from(3)
            } else {
                std::process::ExitCode::FAILURE
            }
        }
    }
}
