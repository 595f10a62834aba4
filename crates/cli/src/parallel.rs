//! Tracing on several threads: the rays are cut into tiles of consecutive rays, which idle
//! threads take in turn (rayon's work stealing), each thread with its own traversal stacks.
//! Every ray is traced by the same code whatever the thread, so the answers are those of one
//! thread, in the rays' order.

use anyhow::{Result, bail};
use rayon::prelude::*;

/// Rays a thread takes at a time: enough to make taking one cheap, few enough that two
/// threads finish together.
pub const TILE: usize = 256;

/// A number of threads to trace on.
pub struct Workers {
    /// `None` for one thread: the caller's own, with no pool at all.
    pool: Option<rayon::ThreadPool>,
}

impl Workers {
    /// `threads` workers (at least 1).
    pub fn new(threads: usize) -> Result<Self> {
        if threads == 0 {
            bail!("--threads must be at least 1");
        }
        let pool = if threads == 1 {
            None
        } else {
            Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .map_err(|error| anyhow::anyhow!("cannot start {threads} threads: {error}"))?,
            )
        };
        Ok(Self { pool })
    }

    /// `answer(state, item)` for every item, in order; each thread makes its `state` (its
    /// stacks) once with `init`. A thread takes [`TILE`] items at a time.
    pub fn map<I, S, T>(
        &self,
        items: &[I],
        init: impl Fn() -> S + Sync + Send,
        answer: impl Fn(&mut S, &I) -> T + Sync + Send,
    ) -> Vec<T>
    where
        I: Sync,
        T: Send,
    {
        self.map_in_tiles(items, TILE, init, answer)
    }

    /// [`Workers::map`] with a thread taking `tile` items at a time (a packet of rays is an
    /// item: a tile of [`TILE`] packets would cut a camera's rays into a handful of pieces,
    /// and one thread would finish long before the other).
    pub fn map_in_tiles<I, S, T>(
        &self,
        items: &[I],
        tile: usize,
        init: impl Fn() -> S + Sync + Send,
        answer: impl Fn(&mut S, &I) -> T + Sync + Send,
    ) -> Vec<T>
    where
        I: Sync,
        T: Send,
    {
        match &self.pool {
            None => {
                let mut state = init();
                items.iter().map(|item| answer(&mut state, item)).collect()
            }
            Some(pool) => pool.install(|| {
                items
                    .par_iter()
                    .with_min_len(tile.max(1))
                    .map_init(&init, |state, item| answer(state, item))
                    .collect()
            }),
        }
    }

    /// How many items `test` holds true for (without keeping the answers).
    pub fn count<I: Sync, S>(
        &self,
        items: &[I],
        init: impl Fn() -> S + Sync + Send,
        test: impl Fn(&mut S, &I) -> bool + Sync + Send,
    ) -> usize {
        match &self.pool {
            None => {
                let mut state = init();
                items.iter().filter(|item| test(&mut state, item)).count()
            }
            Some(pool) => pool.install(|| {
                items
                    .par_iter()
                    .with_min_len(TILE)
                    .map_init(&init, |state, item| test(state, item))
                    .filter(|&hit| hit)
                    .count()
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn answers_keep_their_order_on_any_number_of_threads() {
        let items: Vec<u64> = (0..10_000).collect();
        let one = Workers::new(1).unwrap_or_else(|_| unreachable!());
        let expected = one.map(
            &items,
            || 0u64,
            |calls, item| {
                *calls += 1;
                item * item
            },
        );
        for threads in [2, 3] {
            let workers = Workers::new(threads).unwrap_or_else(|_| unreachable!());
            let got = workers.map(&items, || 0u64, |_, item| item * item);
            assert_eq!(got, expected);
            for tile in [0, 1, 7, 20_000] {
                let got = workers.map_in_tiles(&items, tile, || 0u64, |_, item| item * item);
                assert_eq!(got, expected, "tiles of {tile}");
            }
            assert_eq!(workers.count(&items, || (), |_, item| item % 3 == 0), 3334);
        }
        assert!(Workers::new(0).is_err());
    }
}
