//! The command-line reference (docs/reference/cli.md) is the binary's own `--help` of every
//! command, so it cannot drift: this test renders it from the clap definition and compares
//! it with the committed page. `TETRASIM_BLESS=1 cargo test --release --test cli_reference`
//! rewrites the page after a flag changed.

use clap::CommandFactory as _;

/// The page: a short preamble, then each command's long help as `tetrasim COMMAND --help`
/// prints it.
fn page() -> String {
    let mut cli = tetrasim_cli::cli::Cli::command().term_width(100);
    cli.build();
    let mut out = String::from(
        "# Command-line reference\n\n\
         Every `tetrasim` command with every flag, exactly as `tetrasim COMMAND --help` prints \
         it (generated from the code by `tests/cli_reference.rs`, which fails when this page \
         drifts; `TETRASIM_BLESS=1 cargo test --release --test cli_reference` rewrites it). \
         Every parameter's one name as a flag, scene key and Python keyword: \
         [parameters.md](parameters.md).\n",
    );
    let names: Vec<String> = cli
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .filter(|n| n != "help")
        .collect();
    for name in names {
        let command = cli.find_subcommand_mut(&name).unwrap();
        let help = command.render_long_help().to_string();
        let help: Vec<&str> = help.lines().map(str::trim_end).collect();
        out.push_str(&format!(
            "\n## `tetrasim {name}`\n\n```text\n{}\n```\n",
            help.join("\n")
        ));
    }
    out
}

#[test]
fn the_cli_reference_is_the_binarys_help() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/reference/cli.md");
    let generated = page();
    if std::env::var("TETRASIM_BLESS").is_ok_and(|v| v == "1") {
        std::fs::write(path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        generated == committed,
        "docs/reference/cli.md differs from the commands' --help: rewrite it with \
         `TETRASIM_BLESS=1 cargo test --release --test cli_reference`"
    );
    for command in [
        "run", "plan", "soak", "tradeoff", "bench", "render", "info", "params",
    ] {
        assert!(
            generated.contains(&format!("## `tetrasim {command}`")),
            "{command}"
        );
    }
}
