//! How many of a team's threads run a backend's constraint iterations, chosen by timing the
//! first frames: the largest team [`Team::for_work`] allows is not always the fastest. A
//! barrier's cost depends on the machine: on 16 dedicated cores a team of 16 is not slower
//! than one even on a 371-node mesh, while on a shared 2-core virtual machine a team of two
//! makes the bundled meshes 1.2 to 1.4x slower than one thread (docs/BENCHMARKS.md, "The
//! `cpu` backend's threads").
//!
//! So the iterations run on the team's size and its halvings down to one thread, largest
//! first ([`Team::set_members`]; the step's other passes always use every thread of the
//! team). After one untimed frame, each size runs a frame in turn until one is more than
//! [`SLOWER`] times the fastest so far: it and the smaller ones are dropped, since halving
//! again is not expected to help. The sizes left run in turn until each has run [`ROUNDS`]
//! frames, and the one with the fastest frame runs every frame after that. Where the largest
//! size is clearly fastest, that costs one frame on half the threads. The number of threads
//! never changes a result ([`Team`]), so the choice changes speed only: states are
//! bit-identical whichever size runs which frame.

use std::time::Duration;

use super::team::Team;

/// Frames each remaining candidate runs while the choice is made (its fastest counts).
pub const ROUNDS: u32 = 3;

/// A candidate whose first frame takes more than this times the fastest frame so far ends
/// the descent.
pub const SLOWER: f64 = 1.25;

/// The team, its candidate member counts and their timings, then the chosen count.
#[derive(Debug, Clone)]
pub(super) struct TeamChoice {
    team: Team,
    /// The candidate member counts, largest first; only the chosen one once chosen.
    sizes: Vec<usize>,
    /// Each candidate's fastest timed frame.
    fastest: Vec<Duration>,
    /// Each candidate's timed frames.
    runs: Vec<u32>,
    /// The candidate that runs the next frame.
    next: usize,
    /// Whether the untimed first frame has run.
    warm: bool,
}

impl TeamChoice {
    /// The candidates for `nodes` nodes and groups of `group_size` constraints on average:
    /// [`Team::for_work`]'s size, then its halvings (rounded up) down to 1.
    pub(super) fn for_work(nodes: usize, group_size: usize) -> Self {
        let team = Team::for_work(nodes, group_size);
        let sizes = halvings(team.size());
        Self::new(team, sizes)
    }

    /// A team of the first size choosing among the given sizes, largest first (tests; one
    /// size is a fixed team).
    #[cfg(test)]
    pub(super) fn with_sizes(sizes: &[usize]) -> Self {
        Self::new(Team::with_size(sizes[0]), sizes.to_vec())
    }

    /// `team` choosing among `sizes` (largest first, none above its size).
    fn new(mut team: Team, mut sizes: Vec<usize>) -> Self {
        sizes.retain(|&s| s <= team.size());
        if sizes.is_empty() {
            sizes.push(1);
        }
        team.set_members(sizes[0]);
        TeamChoice {
            team,
            fastest: vec![Duration::MAX; sizes.len()],
            runs: vec![0; sizes.len()],
            sizes,
            next: 0,
            warm: false,
        }
    }

    /// Whether the choice is made (at once for a single candidate).
    pub(super) fn chosen(&self) -> bool {
        self.sizes.len() == 1
    }

    /// The team, with the members that run the next frame.
    pub(super) fn team(&self) -> &Team {
        &self.team
    }

    /// How many members run the next frame.
    #[cfg(test)]
    fn size(&self) -> usize {
        self.team.members()
    }

    /// Records how long the frame that [`Self::team`] ran took and picks the next frame's
    /// team (module docs).
    pub(super) fn record(&mut self, elapsed: Duration) {
        if !self.chosen() {
            self.choose_next(elapsed);
            self.team.set_members(self.sizes[self.next]);
        }
    }

    /// [`Self::record`]'s choice of the next frame's candidate.
    fn choose_next(&mut self, elapsed: Duration) {
        if !self.warm {
            self.warm = true;
            return;
        }
        let k = self.next;
        self.fastest[k] = self.fastest[k].min(elapsed);
        self.runs[k] += 1;
        if self.runs[k] == 1 {
            // The descent: the next size, unless this one is clearly slower.
            let best = self.fastest[..k]
                .iter()
                .min()
                .copied()
                .unwrap_or(Duration::MAX);
            if k > 0 && elapsed.as_secs_f64() > SLOWER * best.as_secs_f64() {
                self.keep(k);
            } else if k + 1 < self.sizes.len() {
                self.next = k + 1;
                return;
            }
        }
        // The rounds: the candidate with the fewest frames, the largest first.
        match (0..self.sizes.len())
            .filter(|&c| self.runs[c] < ROUNDS)
            .min_by_key(|&c| self.runs[c])
        {
            Some(c) => self.next = c,
            None => {
                let best = (0..self.sizes.len())
                    .min_by_key(|&c| (self.fastest[c], c))
                    .unwrap_or(0);
                self.sizes.swap(0, best);
                self.fastest.swap(0, best);
                self.runs.swap(0, best);
                self.keep(1);
            }
        }
    }

    /// Drops the candidates from `count` on.
    fn keep(&mut self, count: usize) {
        self.sizes.truncate(count);
        self.fastest.truncate(count);
        self.runs.truncate(count);
        self.next = self.next.min(count - 1);
    }
}

impl Default for TeamChoice {
    /// A team of one, chosen: the caller's thread.
    fn default() -> Self {
        Self::new(Team::default(), vec![1])
    }
}

/// `size`, then its halvings rounded up, down to 1: 6 -> [6, 3, 2, 1].
fn halvings(size: usize) -> Vec<usize> {
    let mut sizes = vec![size.max(1)];
    while let Some(&last) = sizes.last().filter(|&&s| s > 1) {
        sizes.push(last.div_ceil(2).min(last - 1));
    }
    sizes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ms(t: u64) -> Duration {
        Duration::from_millis(t)
    }

    #[test]
    fn candidates_halve_down_to_one_thread() {
        assert_eq!(halvings(1), [1]);
        assert_eq!(halvings(2), [2, 1]);
        assert_eq!(halvings(6), [6, 3, 2, 1]);
        assert_eq!(halvings(16), [16, 8, 4, 2, 1]);
        assert!(TeamChoice::with_sizes(&[1]).chosen());
    }

    /// Runs frames that take `time(size, frame)` (the first one 100 ms, untimed) until the
    /// choice is made; returns the sizes that ran them and the chosen size.
    fn choose(sizes: &[usize], time: impl Fn(usize, u32) -> Duration) -> (Vec<usize>, usize) {
        let mut choice = TeamChoice::with_sizes(sizes);
        let mut ran = Vec::new();
        while !choice.chosen() {
            assert!(ran.len() < 100, "no choice after {ran:?}");
            let size = choice.size();
            let frame = ran.len() as u32;
            ran.push(size);
            choice.record(if frame == 0 {
                ms(100)
            } else {
                time(size, frame)
            });
        }
        let chosen = choice.size();
        choice.record(ms(1000));
        assert_eq!(choice.size(), chosen, "the choice stays");
        (ran, chosen)
    }

    /// Each size runs a frame, largest first, until one is clearly slower than the fastest
    /// so far (the team of 1 here, 7 ms against 5); the others then run in turn and the one
    /// with the fastest frame is kept.
    #[test]
    fn the_fastest_candidate_is_kept() {
        let time = |size, _| match size {
            4 => ms(9),
            2 => ms(5),
            _ => ms(7),
        };
        let (ran, chosen) = choose(&[4, 2, 1], time);
        assert_eq!(ran, [4, 4, 2, 1, 4, 2, 4, 2]);
        assert_eq!(chosen, 2);
        // Where one thread is fastest, every size runs 3 frames.
        let (ran, chosen) = choose(&[4, 2, 1], |size, _| ms(4 + size as u64));
        assert_eq!(ran.len(), 1 + 3 * 3);
        assert_eq!(chosen, 1);
    }

    /// Where the largest team is clearly fastest, the next size's first frame ends the
    /// choice (16 cores: the horse takes 10 ms on 16 threads, 15 on 8).
    #[test]
    fn a_clearly_fastest_largest_team_costs_one_frame_of_the_next() {
        let (ran, chosen) = choose(&[16, 8, 4, 2, 1], |size, _| ms(160 / size as u64 + 5));
        assert_eq!(ran, [16, 16, 8]);
        assert_eq!(chosen, 16);
    }

    /// One slow frame (another process, say) does not sink a candidate: its fastest frame
    /// counts. A tie goes to the larger team.
    #[test]
    fn a_candidate_keeps_its_fastest_frame() {
        let time = |size, frame| match (size, frame) {
            (2, 1) => ms(40),
            _ => ms(6),
        };
        let (ran, chosen) = choose(&[2, 1], time);
        assert_eq!(ran, [2, 2, 1, 2, 1, 2, 1]);
        assert_eq!(chosen, 2);
    }
}
