//! `--shard I/N`: one of N deterministic, disjoint parts of a batch, for running a batch on
//! many machines (GNU parallel, Slurm array jobs, Kubernetes Indexed Jobs; docs/batch.md).
//!
//! Pair k (0-based, in manifest order, or the sorted order of folder mode) belongs to shard
//! `k mod N + 1`. Index-mod keeps the shards within one pair of each other in size whatever
//! the names, and neighbours in a manifest (often alike in cost: one icon family) spread over
//! the shards; a hash of the output path would keep a pair's shard when rows are inserted
//! above it, but gives shards of uneven size on small batches. The shards of one manifest
//! partition it: every pair in exactly one.

use std::fmt;
use std::str::FromStr;

/// Shard `index` of `count` (1-based: `1/N` … `N/N`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Shard {
    /// Which shard, from 1 to `count`.
    pub(crate) index: usize,
    /// How many shards.
    pub(crate) count: usize,
}

/// Most shards: far more machines than a batch has, and small enough to print in a name.
const MAX_SHARDS: usize = 1_000_000;

impl FromStr for Shard {
    type Err = String;

    /// `I/N` with 1 ≤ I ≤ N.
    fn from_str(s: &str) -> Result<Self, String> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| format!("'{s}' is not I/N, e.g. 3/8 (shard 3 of 8)"))?;
        let number = |v: &str, what: &str| -> Result<usize, String> {
            v.trim()
                .parse::<usize>()
                .map_err(|_| format!("'{v}' in '{s}' is not a whole number ({what})"))
        };
        let (index, count) = (number(i, "the shard")?, number(n, "the count")?);
        if count == 0 || count > MAX_SHARDS {
            return Err(format!(
                "'{s}': the count of shards must be from 1 to {MAX_SHARDS}"
            ));
        }
        if index == 0 || index > count {
            return Err(format!(
                "'{s}': the shard must be from 1 to {count} (shards are numbered from 1)"
            ));
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    /// `I-of-N`, as in report names (`batch-report.3-of-8.jsonl`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-of-{}", self.index, self.count)
    }
}

impl Shard {
    /// Whether the pair at 0-based position `k` belongs to this shard.
    pub(crate) fn holds(&self, k: usize) -> bool {
        k % self.count == self.index - 1
    }
}

/// The items of `items` that `shard` holds (all of them without one), with their 0-based
/// positions, in order.
pub(crate) fn select<T>(items: &[T], shard: Option<Shard>) -> Vec<(usize, &T)> {
    items
        .iter()
        .enumerate()
        .filter(|(k, _)| shard.is_none_or(|s| s.holds(*k)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn parses_and_refuses() {
        assert_eq!("3/8".parse(), Ok(Shard { index: 3, count: 8 }));
        assert_eq!(" 1 / 1 ".parse(), Ok(Shard { index: 1, count: 1 }));
        for bad in ["0/3", "4/3", "1/0", "3", "a/b", "-1/3", "1/3/4", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
        assert_eq!(Shard { index: 3, count: 8 }.to_string(), "3-of-8");
    }

    #[test]
    fn index_mod_n() {
        let items: Vec<usize> = (0..7).collect();
        let s2 = select(&items, Some(Shard { index: 2, count: 3 }));
        assert_eq!(s2, [(1, &1), (4, &4)]);
        assert_eq!(select(&items, None).len(), 7);
    }

    proptest! {
        /// The shards of any batch partition it: every pair in exactly one shard, in order,
        /// and the shards' sizes differ by one at most.
        #[test]
        fn shards_partition_the_batch(len in 0usize..200, count in 1usize..40) {
            let items: Vec<usize> = (0..len).collect();
            let mut seen = vec![0; len];
            let mut sizes = Vec::new();
            for index in 1..=count {
                let part = select(&items, Some(Shard { index, count }));
                prop_assert!(part.windows(2).all(|w| w[0].0 < w[1].0));
                for (k, &v) in &part {
                    prop_assert_eq!(*k, v);
                    seen[*k] += 1;
                }
                sizes.push(part.len());
            }
            prop_assert!(seen.iter().all(|&n| n == 1));
            let (lo, hi) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
            prop_assert!(hi - lo <= 1);
        }
    }
}
