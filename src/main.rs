//! `tetrasim` command line: parses arguments and hands them to [`tetrasim_cli::cli::execute`].

use clap::Parser;

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().collect();
    for warning in tetrasim_cli::renamed::flag_warnings(&args) {
        eprintln!("{warning}");
    }
    let cli = tetrasim_cli::cli::Cli::parse();
    let by_flags = cli.set_by_flags();
    match tetrasim_cli::cli::execute(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // A divergence's advice names settings as the caller set them: flags, or a
            // scene's keys.
            let diverged = e.downcast_ref::<tetrasim_cli::cli::DivergedRun>().is_some()
                || matches!(e.downcast_ref(), Some(tetrasim::Error::Diverged(_)));
            let message = format!("{e:#}");
            match diverged && by_flags {
                true => eprintln!("error: {}", tetrasim_cli::cli::in_flags(&message)),
                false => eprintln!("error: {message}"),
            }
            // A diverged run exits with 3 (docs/STABILITY.md), a bad scene file with 2 (as
            // clap does for bad flags), a run ended by SIGINT or SIGTERM with 130 (as a
            // shell reports an interrupted command); other failures with 1.
            if e.downcast_ref::<tetrasim_cli::cli::InterruptedRun>()
                .is_some()
            {
                std::process::ExitCode::from(130)
            } else if diverged {
                std::process::ExitCode::from(3)
            } else if e.downcast_ref::<tetrasim_cli::cli::BadScene>().is_some() {
                std::process::ExitCode::from(2)
            } else {
                std::process::ExitCode::FAILURE
            }
        }
    }
}
