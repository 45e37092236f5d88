//! What the CPU backends (`cpu-ref`, `cpu`) need of the machine's memory, and whether the
//! machine has it: checked before a backend is built, so a problem too large for the
//! machine is refused with both sizes instead of being killed half-way by the kernel.
//!
//! The need is an upper bound measured, not derived: the peak resident memory of
//! `tetrasim run --frames 3` (the mesh read, the model and problem built, the backend run,
//! resting on the floor) on four meshes of 2,857 to 212,801 tets grows by 410 to 890 bytes
//! per tet over the methods and both backends (`mss` least, `neo-hookean` on `cpu-ref`
//! most) on 9 to 16 MiB for the process (docs/STABILITY.md, "Memory, said before it
//! bites"). [`needs`] asks [`BASE_BYTES`] plus [`BYTES_PER_TET`] per tet, above every one
//! of them.

use crate::error::{Error, Result};
use crate::gpu::memory::mib;
use crate::problem::Problem;

/// The process's share that does not grow with the mesh [bytes].
pub const BASE_BYTES: u64 = 16 << 20;

/// What each tet adds at most [bytes]: its springs or elements, the nodes it brings, the
/// colouring and contact structures, for any method.
pub const BYTES_PER_TET: u64 = 1024;

/// The memory a CPU backend may take for `problem` at most [bytes].
pub fn needs(problem: &Problem) -> u64 {
    BASE_BYTES + BYTES_PER_TET * problem.model.tets.len() as u64
}

/// The memory the machine offers a new allocation now [bytes]: Linux's `MemAvailable`,
/// less where the process's cgroup sets a lower limit (`memory.max` less
/// `memory.current`); `None` where neither is known (another system).
pub fn machine_offers() -> Option<u64> {
    let available = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| meminfo_available(&text));
    let cgroup = cgroup_remaining(
        std::fs::read_to_string("/sys/fs/cgroup/memory.max").ok(),
        std::fs::read_to_string("/sys/fs/cgroup/memory.current").ok(),
    );
    match (available, cgroup) {
        (Some(a), Some(c)) => Some(a.min(c)),
        (a, c) => a.or(c),
    }
}

/// `MemAvailable` of a `/proc/meminfo` text [bytes].
fn meminfo_available(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// What a cgroup v2 limit leaves [bytes]: `memory.max` less `memory.current`; `None`
/// without a limit (`max`) or without the files.
fn cgroup_remaining(max: Option<String>, current: Option<String>) -> Option<u64> {
    let max: u64 = max?.trim().parse().ok()?;
    let current: u64 = current?.trim().parse().ok()?;
    Some(max.saturating_sub(current))
}

/// Refuses a problem whose [`needs`] exceed what the machine offers (at most `limit`
/// bytes of it, when given: `--device-memory`), naming `backend` and both sizes.
pub fn check(backend: &str, problem: &Problem, limit: Option<u64>) -> Result<()> {
    compare(
        backend,
        needs(problem),
        problem.model.tets.len(),
        machine_offers(),
        limit,
    )
}

/// [`check`] on given sizes: `offers` `None` is an unknown machine, checked only against
/// `limit`.
fn compare(
    backend: &str,
    needs: u64,
    tets: usize,
    offers: Option<u64>,
    limit: Option<u64>,
) -> Result<()> {
    let (offers, source) = match (offers, limit) {
        (Some(o), Some(l)) if l < o => (l, " (the --device-memory limit)"),
        (Some(o), _) => (o, " (available now)"),
        (None, Some(l)) => (l, " (the --device-memory limit)"),
        (None, None) => return Ok(()),
    };
    if needs <= offers {
        return Ok(());
    }
    Err(Error::Memory(format!(
        "the {backend} backend needs up to {} of memory for this problem ({tets} tets), the \
         machine offers {}{source}",
        mib(needs),
        mib(offers)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    const MIB: u64 = 1 << 20;

    #[test]
    fn meminfo_gives_the_available_bytes() {
        let text = "MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   2048 kB\n";
        assert_eq!(meminfo_available(text), Some(2048 * 1024));
        assert_eq!(meminfo_available("MemTotal: 5 kB\n"), None);
    }

    #[test]
    fn a_cgroup_limit_leaves_its_remainder() {
        let some = |s: &str| Some(s.to_string());
        assert_eq!(cgroup_remaining(some("1000\n"), some("400\n")), Some(600));
        assert_eq!(cgroup_remaining(some("1000\n"), some("4000\n")), Some(0));
        assert_eq!(cgroup_remaining(some("max\n"), some("400\n")), None);
        assert_eq!(cgroup_remaining(None, some("400\n")), None);
    }

    #[test]
    fn a_need_above_the_offer_is_refused_naming_both() {
        assert!(compare("cpu", 10 * MIB, 5, Some(20 * MIB), None).is_ok());
        let err = compare("cpu", 30 * MIB, 5, Some(20 * MIB), None).unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, Error::Memory(_)));
        assert!(
            text.contains("30.00 MiB") && text.contains("20.00 MiB"),
            "{text}"
        );
        assert!(
            text.contains("(5 tets)") && text.contains("available now"),
            "{text}"
        );
    }

    #[test]
    fn the_limit_caps_the_offer_and_stands_alone_on_an_unknown_machine() {
        let text = compare("cpu-ref", 10 * MIB, 5, Some(20 * MIB), Some(MIB))
            .unwrap_err()
            .to_string();
        assert!(text.contains("cpu-ref") && text.contains("1.00 MiB (the --device-memory limit)"));
        assert!(compare("cpu", 10 * MIB, 5, None, None).is_ok());
        assert!(compare("cpu", 10 * MIB, 5, None, Some(MIB)).is_err());
        assert!(compare("cpu", 10 * MIB, 5, Some(20 * MIB), Some(40 * MIB)).is_ok());
    }

    #[test]
    fn this_machine_says_what_it_offers() {
        if cfg!(target_os = "linux") {
            let offers = machine_offers().expect("Linux has /proc/meminfo");
            assert!(offers > 16 * MIB, "{offers} bytes on offer");
        }
    }
}
