//! A reusable barrier for a fixed team of threads that spins briefly, then yields, then
//! sleeps: the phases it separates last microseconds, far less than a sleep and wake-up would
//! cost, and yielding keeps it live when the team has fewer cores than threads; a thread that
//! has yielded for [`YIELD_BEFORE_SLEEP`] sleeps on a condition variable, so that teams that
//! share too few cores (tests running side by side, say) do not burn them waiting.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use crossbeam_utils::Backoff;

/// How long a waiting thread yields before it sleeps: far longer than a phase of a step
/// on a team with a core per thread, so that sleeping (and the wake-up's tens of
/// microseconds) happens only when the threads share cores.
pub(super) const YIELD_BEFORE_SLEEP: Duration = Duration::from_micros(500);

/// A barrier for `size` threads (generation counting: reusable at once, phase after
/// phase). Everything a thread wrote before [`SpinBarrier::wait`] is visible to every
/// thread after it returns.
#[derive(Debug)]
pub(super) struct SpinBarrier {
    size: usize,
    /// Threads that have arrived in the current generation.
    arrived: AtomicUsize,
    /// Bumped by the last thread to arrive (holding `sleepers`' lock), which releases the
    /// others.
    generation: AtomicUsize,
    /// The number of threads asleep on `wake`.
    sleepers: Mutex<usize>,
    wake: Condvar,
}

impl SpinBarrier {
    /// A barrier for `size` threads (at least 1).
    pub(super) fn new(size: usize) -> Self {
        SpinBarrier {
            size: size.max(1),
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            sleepers: Mutex::new(0),
            wake: Condvar::new(),
        }
    }

    /// The sleepers' count, locked (a panic elsewhere cannot leave it inconsistent).
    fn sleepers(&self) -> MutexGuard<'_, usize> {
        self.sleepers.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Blocks until all `size` threads have called `wait` in this generation.
    pub(super) fn wait(&self) {
        let generation = self.generation.load(Ordering::Acquire);
        // AcqRel: the arrivals form one release sequence, so the last thread to arrive
        // has seen every write made before any arrival.
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.size {
            self.arrived.store(0, Ordering::Relaxed);
            // Under the lock, so that a thread going to sleep either sees the new
            // generation or is counted before it is read here.
            let sleeping = {
                let sleepers = self.sleepers();
                // Release: publishes the reset and everything the last thread has seen.
                self.generation.fetch_add(1, Ordering::Release);
                *sleepers
            };
            if sleeping > 0 {
                self.wake.notify_all();
            }
            return;
        }
        let released = || self.generation.load(Ordering::Acquire) != generation;
        let backoff = Backoff::new();
        while !backoff.is_completed() {
            if released() {
                return;
            }
            backoff.snooze();
        }
        let start = Instant::now();
        while start.elapsed() < YIELD_BEFORE_SLEEP {
            if released() {
                return;
            }
            std::thread::yield_now();
        }
        let mut sleepers = self.sleepers();
        *sleepers += 1;
        while !released() {
            sleepers = (self.wake.wait(sleepers)).unwrap_or_else(PoisonError::into_inner);
        }
        *sleepers -= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every thread sees every other thread's phase-`p` write after the `p`-th wait, with
    /// more threads than this machine may have cores (so some sleep).
    #[test]
    fn phases_are_separated() {
        const THREADS: usize = 8;
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

    /// Threads that wait past [`YIELD_BEFORE_SLEEP`] sleep and are woken: one thread
    /// arrives 2 ms late at every phase.
    #[test]
    fn sleepers_are_woken() {
        const THREADS: usize = 3;
        let barrier = SpinBarrier::new(THREADS);
        let phases = AtomicUsize::new(0);
        std::thread::scope(|s| {
            for t in 0..THREADS {
                let (barrier, phases) = (&barrier, &phases);
                s.spawn(move || {
                    for _ in 0..5 {
                        if t == 0 {
                            std::thread::sleep(Duration::from_millis(2));
                            phases.fetch_add(1, Ordering::Relaxed);
                        }
                        barrier.wait();
                    }
                });
            }
        });
        assert_eq!(phases.load(Ordering::Relaxed), 5);
    }
}
