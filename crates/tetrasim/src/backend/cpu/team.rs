//! A fixed team of threads that runs a whole step's constraint iterations together: one
//! wake-up per step instead of two rayon fork-joins per constraint group, each thread
//! owning fixed blocks of constraints and nodes and a [`SpinBarrier`] between phases.
//!
//! The team is a private rayon pool of its own: a barrier needs every member running at
//! once, which a shared pool (busy with other work, or with another team's broadcast)
//! cannot promise. Its size is rayon's thread count where the backend is built
//! (`RAYON_NUM_THREADS`, or the pool it is built in), capped so that each thread gets
//! enough work to outweigh its barriers; the backend then times that many threads and fewer
//! on its first frames and keeps the fastest ([`super::team_choice`]). The step's other
//! passes run on the same threads ([`Team::install`]), so that no second set of threads
//! competes with the team. Results never depend on the size: each element is computed by
//! exactly one thread with the same arithmetic whatever the partition.

use std::ops::Range;

use super::barrier::SpinBarrier;

/// Fewest nodes per team member: below this a barrier costs more than the work it
/// separates. Measured on 16 cores (docs/BENCHMARKS.md): with no cap at all, 16 threads
/// were not slower than one even on the bundled 371-node box, and a cap of 512 nodes (8
/// threads on the 4.6k-node bunny) cost the bunny a third of its 16-thread speed; this
/// only keeps teams off toy meshes. Where barriers cost more (a shared 2-core virtual
/// machine), [`super::team_choice::TeamChoice`] finds that by timing.
pub const MIN_NODES_PER_THREAD: usize = 64;

/// Fewest constraints per team member in an average group (as
/// [`MIN_NODES_PER_THREAD`]).
pub const MIN_CONSTRAINTS_PER_THREAD: usize = 32;

/// A team of threads that run one closure together ([`Team::run`]).
#[derive(Debug)]
pub(super) struct Team {
    size: usize,
    /// The team's threads (none for a team of one, which runs on the caller).
    pool: Option<rayon::ThreadPool>,
    /// How many of the threads run [`Team::run`]'s closure (the others return at once;
    /// [`Team::install`]'s parallel iterators use them all): `size` unless set lower
    /// ([`Team::set_members`]).
    members: usize,
}

impl Team {
    /// A team for `nodes` nodes and groups of `group_size` constraints on average: rayon's
    /// current thread count, capped by [`MIN_NODES_PER_THREAD`] and
    /// [`MIN_CONSTRAINTS_PER_THREAD`]. A team that cannot start its threads runs alone.
    pub(super) fn for_work(nodes: usize, group_size: usize) -> Self {
        let size = rayon::current_num_threads()
            .min(nodes / MIN_NODES_PER_THREAD)
            .min(group_size / MIN_CONSTRAINTS_PER_THREAD)
            .max(1);
        Self::with_size(size)
    }

    /// The number of threads in the team.
    pub(super) fn size(&self) -> usize {
        self.size
    }

    /// A team of `size` threads (one if they cannot be started).
    pub(super) fn with_size(size: usize) -> Self {
        let pool = (size > 1)
            .then(|| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(size)
                    .thread_name(|i| format!("tetrasim-cpu-{i}"))
                    .build()
                    .ok()
            })
            .flatten();
        let size = if pool.is_some() { size } else { 1 };
        Team {
            size,
            pool,
            members: size,
        }
    }

    /// How many of the team's threads run [`Team::run`]'s closure from now on: `members`,
    /// at least 1 and at most the team's size. The others only take part in
    /// [`Team::install`]'s parallel iterators.
    pub(super) fn set_members(&mut self, members: usize) {
        self.members = members.clamp(1, self.size);
    }

    /// How many threads run [`Team::run`]'s closure.
    #[cfg(test)]
    pub(super) fn members(&self) -> usize {
        self.members
    }

    /// Runs `op` on the team's pool, so that its parallel iterators use the team's threads
    /// (on the caller, in rayon's current pool, for a team of one).
    pub(super) fn install<R: Send>(&self, op: impl FnOnce() -> R + Send) -> R {
        match &self.pool {
            Some(pool) => pool.install(op),
            None => op(),
        }
    }

    /// Runs `op` once on every member (the first threads, as many as
    /// [`Team::set_members`] gave; on the caller for one) at the same time and returns when
    /// all have finished.
    /// `op` must call [`Member::wait`] the same number of times on every member; a panic
    /// in one member leaves the others waiting forever.
    pub(super) fn run(&self, op: impl Fn(Member<'_>) + Sync) {
        let members = self.members;
        let barrier = SpinBarrier::new(members);
        match &self.pool {
            Some(pool) if members > 1 => {
                pool.broadcast(|context| {
                    if context.index() < members {
                        op(Member {
                            index: context.index(),
                            size: members,
                            barrier: &barrier,
                        })
                    }
                });
            }
            _ => op(Member {
                index: 0,
                size: 1,
                barrier: &barrier,
            }),
        }
    }
}

impl Default for Team {
    /// A team of one: the caller's thread.
    fn default() -> Self {
        Self::with_size(1)
    }
}

impl Clone for Team {
    /// A new team of the same size and members: two backends never share threads, so a
    /// barrier never waits for a thread busy with the other.
    fn clone(&self) -> Self {
        let mut team = Self::with_size(self.size);
        team.set_members(self.members);
        team
    }
}

/// One thread of a running team.
#[derive(Debug, Clone, Copy)]
pub(super) struct Member<'a> {
    index: usize,
    size: usize,
    barrier: &'a SpinBarrier,
}

impl Member<'_> {
    /// This member's block of `0..len`: the `index`-th of `size` contiguous, near-equal
    /// parts.
    pub(super) fn block(&self, len: usize) -> Range<usize> {
        len * self.index / self.size..len * (self.index + 1) / self.size
    }

    /// This member's block of `0..ends.len() - 1` items weighted by `ends`, their running
    /// total (`ends[0] = 0`, item `k` weighs `ends[k + 1] - ends[k]`): the `index`-th of
    /// `size` contiguous parts of near-equal weight.
    pub(super) fn weighted_block(&self, ends: &[usize]) -> Range<usize> {
        let items = ends.len().saturating_sub(1);
        let total = ends.last().copied().unwrap_or(0);
        let boundary = |part: usize| match part == self.size {
            true => items,
            false => ends
                .partition_point(|&e| e < total * part / self.size)
                .min(items),
        };
        boundary(self.index)..boundary(self.index + 1)
    }

    /// Whether this is the team's first member (the one that runs serial work).
    pub(super) fn leads(&self) -> bool {
        self.index == 0
    }

    /// Waits until every member has reached the same point: what any member wrote before
    /// is visible to all after.
    pub(super) fn wait(&self) {
        if self.size > 1 {
            self.barrier.wait();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The members' weighted blocks tile the items in order, and none weighs more than an
    /// even share plus one item (which blocks of equal counts would break here).
    #[test]
    fn weighted_blocks_tile_the_items_evenly() {
        let barrier = SpinBarrier::new(1);
        // Light items, then heavy ones (a step's springs, then its tets), some of none.
        let weights: Vec<usize> = (0..200)
            .map(|k| if k < 100 { 1 + k % 2 } else { 4 * (k % 3) })
            .collect();
        for size in 1..=9 {
            for items in [0, 1, 5, 37, 200] {
                let mut ends = vec![0];
                for w in &weights[..items] {
                    ends.push(ends.last().unwrap() + w);
                }
                let total = ends[items];
                let heaviest = weights[..items].iter().copied().max().unwrap_or(0);
                let mut next = 0;
                for index in 0..size {
                    let member = Member {
                        index,
                        size,
                        barrier: &barrier,
                    };
                    let block = member.weighted_block(&ends);
                    assert_eq!(
                        block.start, next,
                        "size {size}, {items} items, member {index}"
                    );
                    let weight = ends[block.end] - ends[block.start];
                    assert!(
                        weight <= total.div_ceil(size) + heaviest,
                        "size {size}, {items} items, member {index}: {weight} of {total}"
                    );
                    next = block.end;
                }
                assert_eq!(next, items, "size {size}, {items} items");
            }
        }
    }
}
