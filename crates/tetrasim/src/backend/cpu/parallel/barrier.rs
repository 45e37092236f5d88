//! A reusable barrier for a fixed team of threads that spins briefly, then yields: the
//! phases it separates last microseconds, far less than a sleep and wake-up would cost,
//! and yielding keeps it live when the team has fewer cores than threads.

use std::sync::atomic::{AtomicUsize, Ordering};

use crossbeam_utils::Backoff;

/// A barrier for `size` threads (generation counting: reusable at once, phase after
/// phase). Everything a thread wrote before [`SpinBarrier::wait`] is visible to every
/// thread after it returns.
#[derive(Debug)]
pub(super) struct SpinBarrier {
    size: usize,
    /// Threads that have arrived in the current generation.
    arrived: AtomicUsize,
    /// Bumped by the last thread to arrive, which releases the others.
    generation: AtomicUsize,
}

impl SpinBarrier {
    /// A barrier for `size` threads (at least 1).
    pub(super) fn new(size: usize) -> Self {
        SpinBarrier {
            size: size.max(1),
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
        }
    }

    /// Blocks until all `size` threads have called `wait` in this generation.
    pub(super) fn wait(&self) {
        let generation = self.generation.load(Ordering::Acquire);
        // AcqRel: the arrivals form one release sequence, so the last thread to arrive
        // has seen every write made before any arrival.
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.size {
            self.arrived.store(0, Ordering::Relaxed);
            // Release: publishes the reset and everything the last thread has seen.
            self.generation.fetch_add(1, Ordering::Release);
            return;
        }
        let backoff = Backoff::new();
        while self.generation.load(Ordering::Acquire) == generation {
            backoff.snooze();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every thread sees every other thread's phase-`p` write after the `p`-th wait.
    #[test]
    fn phases_are_separated() {
        const THREADS: usize = 4;
        const PHASES: usize = 2000;
        let barrier = SpinBarrier::new(THREADS);
        let counters: Vec<AtomicUsize> = (0..THREADS).map(|_| AtomicUsize::new(0)).collect();
        std::thread::scope(|s| {
            for t in 0..THREADS {
                let (barrier, counters) = (&barrier, &counters);
                s.spawn(move || {
                    for phase in 0..PHASES {
                        counters[t].store(phase + 1, Ordering::Relaxed);
                        barrier.wait();
                        for c in counters {
                            assert_eq!(c.load(Ordering::Relaxed), phase + 1);
                        }
                        barrier.wait();
                    }
                });
            }
        });
    }
}
