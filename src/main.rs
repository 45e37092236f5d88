//! `tetrasim` command line: parses arguments and hands them to [`tetrasim::cli::execute`].

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = tetrasim::cli::Cli::parse();
    match tetrasim::cli::execute(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
