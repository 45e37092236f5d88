//! Refuses, before any output is made, a run whose frame files would not fit the free
//! space of their disk: frame 0 is written once to the system's temporary folder to learn
//! a frame file's size, and that size times the files the run writes is compared with what
//! the output folder's file system has free for this user. A disk that fills anyway (other
//! writers, a frame larger than the first) ends the run with the write's error, every frame
//! before it whole: each file goes to a temporary name and is renamed when complete.

use std::path::Path;

use tetrascene::scene::{Output, DEFAULT_EVERY};
use tetrasim::backend::State;
use tetrasim::error::{Error, Result};
use tetrasim::gpu::memory::mib;
use tetrasim::model::Model;
use tetrasim::output::{write_frame, OutputFormat, OutputUnits};

/// Refuses the frame files `output` asks for, for `runs` runs of `frames` frames of
/// `model`, where they would not fit the free space of the output folder's disk. Does
/// nothing without an output folder, nor for a USD stage (one file, written at the end).
pub fn check_disk_space(output: &Output, model: &Model, runs: usize, frames: u32) -> Result<()> {
    let Some(dir) = &output.dir else {
        return Ok(());
    };
    let format = output.format.unwrap_or_default();
    if format == OutputFormat::Usd {
        return Ok(());
    }
    let every = output.every.unwrap_or(DEFAULT_EVERY).max(1);
    let probe = tempfile::Builder::new()
        .prefix("tetrasim-frame-size")
        .suffix(&format!(".{}", format.extension()))
        .tempfile()
        .map_err(|e| Error::io(std::env::temp_dir(), e))?;
    let state = State {
        positions: model.positions.clone(),
        velocities: model.velocities.clone(),
    };
    let units = output.units.unwrap_or(OutputUnits::Simulation);
    write_frame(probe.path(), format, units, model, &state)?;
    let per_file = std::fs::metadata(probe.path())
        .map_err(|e| Error::io(probe.path(), e))?
        .len();
    let files = u64::from(frames / every + 1) * runs as u64;
    let free = free_space(dir)?;
    refuse_beyond(dir, per_file, files, free)
}

/// The error when `files` files of `per_file` bytes exceed `free` bytes.
fn refuse_beyond(dir: &Path, per_file: u64, files: u64, free: u64) -> Result<()> {
    let needs = per_file.saturating_mul(files);
    if needs <= free {
        return Ok(());
    }
    Err(Error::io(
        dir,
        std::io::Error::other(format!(
            "the run would write about {} of frames ({files} files of {}), and the disk \
                 has {} free: write fewer frames (--every, --frames) or free some space",
            mib(needs),
            mib(per_file),
            mib(free)
        )),
    ))
}

/// Bytes this user may still write on the file system of `dir` (or of its nearest
/// existing parent, when it is yet to be made).
fn free_space(dir: &Path) -> Result<u64> {
    let absolute = std::path::absolute(dir).map_err(|e| Error::io(dir, e))?;
    let existing = absolute
        .ancestors()
        .find(|p| p.exists())
        .unwrap_or(Path::new("/"));
    let stats = rustix::fs::statvfs(existing).map_err(|e| Error::io(existing, e.into()))?;
    Ok(stats.f_bavail.saturating_mul(stats.f_frsize))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_beyond_the_free_space_are_refused_with_both_sizes() {
        let dir = Path::new("out");
        assert!(refuse_beyond(dir, 1 << 20, 10, 10 << 20).is_ok());
        let err = refuse_beyond(dir, 1 << 20, 11, 10 << 20)
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("out: the run would write about 11.00 MiB"),
            "{err}"
        );
        assert!(err.contains("11 files of 1.00 MiB"), "{err}");
        assert!(err.contains("the disk has 10.00 MiB free"), "{err}");
    }

    #[test]
    fn the_free_space_of_a_folder_yet_to_be_made_is_its_parents() {
        let here = tempfile::tempdir().unwrap();
        let free = free_space(here.path()).unwrap();
        assert!(free > 0);
        let later = here.path().join("a/b/c");
        let free_later = free_space(&later).unwrap();
        // The same file system, measured moments apart.
        assert!(
            free_later.abs_diff(free) < free / 10,
            "{free} against {free_later}"
        );
    }
}
