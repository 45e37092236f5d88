//! `run`'s output flags, which the commands that write no run output (`plan`, `soak`)
//! refuse by name rather than ignore.

use super::RunArgs;

/// The output flags of `args`, each with whether it is given, in `--help`'s order.
pub fn output_flags(args: &RunArgs) -> [(&'static str, bool); 7] {
    [
        ("json", args.json.is_some()),
        ("out-dir", args.out_dir.is_some()),
        ("every", args.every.is_some()),
        ("format", args.format.is_some()),
        ("units", args.units.is_some()),
        ("checkpoint", args.checkpoint.is_some()),
        ("resume", args.resume.is_some()),
    ]
}

/// Refuses the first flag in `given` that is on, saying why (`why`) in the command's words.
pub fn refuse_given(given: &[(&'static str, bool)], why: &str) -> tetrasim::Result<()> {
    match given.iter().find(|(_, on)| *on) {
        Some((flag, _)) => Err(tetrasim::Error::param(*flag, why)),
        None => Ok(()),
    }
}
