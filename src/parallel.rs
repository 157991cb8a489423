//! When a batch of work goes to rayon's threads and when it stays on the calling thread.
//!
//! Handing a batch to rayon wakes its workers, which spin a while before they sleep again:
//! tens of microseconds of CPU per batch, however small the batch. Automatic mode checks each
//! mesh a few frames at a time, and the animated SVG is made a few keyframes at a time, so on
//! an icon pair of a few hundred vertices those hand-offs cost more CPU than the batches and
//! gained no wall time (issue 16, measured on the 40 corpus pairs around the median). A batch
//! smaller than [`MIN_WORK`] therefore runs on the calling thread. Every batch is a map of
//! independent items, so the results are the same either way, bit for bit.

use rayon::prelude::*;

/// Units of work (points solved, warped or written, each tens of nanoseconds) below which a
/// batch runs on the calling thread: about a millisecond of work.
pub(crate) const MIN_WORK: usize = 1 << 14;

/// Whether a batch of `work` units is worth rayon's threads.
pub(crate) fn worth(work: usize) -> bool {
    work >= MIN_WORK
}

/// `f` of every item, in the items' order: on rayon's threads when the whole batch's `work`
/// is [`worth`] it, else on the calling thread.
pub(crate) fn map<I: Sync, T: Send>(
    items: &[I],
    work: usize,
    f: impl Fn(&I) -> T + Sync + Send,
) -> Vec<T> {
    if worth(work) {
        items.par_iter().map(f).collect()
    } else {
        items.iter().map(f).collect()
    }
}

/// [`map`] with a scratch value per thread made by `init` (one in all on the calling thread).
pub(crate) fn map_init<I: Sync, W, T: Send>(
    items: &[I],
    work: usize,
    init: impl Fn() -> W + Sync + Send,
    f: impl Fn(&mut W, &I) -> T + Sync + Send,
) -> Vec<T> {
    if worth(work) {
        items.par_iter().map_init(init, f).collect()
    } else {
        let mut w = init();
        items.iter().map(|i| f(&mut w, i)).collect()
    }
}

/// Items per batch when `len` items of `work` units in all are grouped into batches of at most
/// `max` (frames that share a pass over a factor): as large as it may be, but small enough
/// that every thread [`map_init`] uses gets a batch.
pub(crate) fn batch_len(len: usize, work: usize, max: usize) -> usize {
    let threads = if worth(work) {
        rayon::current_num_threads()
    } else {
        1
    };
    let batches = len.div_ceil(max.max(1)).max(threads.min(len)).max(1);
    len.div_ceil(batches).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batches_are_full_unless_a_thread_would_go_without() {
        // On the calling thread: batches as large as allowed.
        assert_eq!(batch_len(30, 0, 8), 8);
        assert_eq!(batch_len(5, 0, 8), 5);
        assert_eq!(batch_len(0, 0, 8), 1);
        assert_eq!(batch_len(3, 0, 0), 1);
        // On rayon's threads: enough batches for every thread, none above the limit.
        let threads = rayon::current_num_threads();
        for len in 1..40 {
            let b = batch_len(len, usize::MAX, 8);
            assert!((1..=8).contains(&b), "{len} items: batches of {b}");
            assert!(
                len.div_ceil(b) >= threads.min(len),
                "{len} items in batches of {b} leave some of {threads} threads idle"
            );
            assert!(len.div_ceil(b) <= len.div_ceil(8).max(threads.min(len)));
        }
    }

    #[test]
    fn both_ways_give_the_items_in_order() {
        let items: Vec<usize> = (0..1000).collect();
        for work in [0, MIN_WORK - 1, MIN_WORK, usize::MAX] {
            assert_eq!(
                map(&items, work, |&i| i * 3),
                (0..1000).map(|i| i * 3).collect::<Vec<_>>()
            );
            let got = map_init(&items, work, || 7usize, |w, &i| *w + i);
            assert_eq!(got, (7..1007).collect::<Vec<_>>());
        }
    }

    #[test]
    fn small_batches_stay_on_the_calling_thread() {
        let here = std::thread::current().id();
        let items = [0u8; 8];
        let small = map(&items, MIN_WORK - 1, |_| std::thread::current().id());
        assert!(small.iter().all(|&id| id == here));
        // A batch worth it runs on rayon's workers (the calling thread is not one of them).
        let big = map(&items, MIN_WORK, |_| std::thread::current().id());
        assert!(big.iter().all(|&id| id != here));
    }
}
