//! SIGINT and SIGTERM end a run after the frames it has started (docs/FORMATS.md,
//! "Interrupted runs"): the command line's `run` listens for them
//! ([`listen_for_interrupts`]), and [`super::run`] hands the flag they set to the engine's
//! driver ([`tetrasim::sim::Simulation::stop_on`]), which submits no further frame. The run
//! then writes its frames' series, checkpoint and record as at its end, marked
//! `"interrupted": true`, and `tetrasim` exits with status 130.

use std::sync::atomic::AtomicBool;
use std::sync::{Arc, OnceLock};

/// The flag the signals set, once something listens for them.
static INTERRUPTED: OnceLock<Arc<AtomicBool>> = OnceLock::new();

/// From now on SIGINT and SIGTERM set the flag runs stop on, instead of ending the process
/// at once. Idempotent.
pub fn listen_for_interrupts() -> std::io::Result<()> {
    let mut result = Ok(());
    INTERRUPTED.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
            if let Err(e) = signal_hook::flag::register(signal, Arc::clone(&flag)) {
                result = Err(e);
            }
        }
        flag
    });
    result
}

/// The flag runs stop on, when something listens for the signals.
pub fn interrupt_flag() -> Option<Arc<AtomicBool>> {
    INTERRUPTED.get().cloned()
}
