//! Frames made in parallel chunks and consumed in order: the streaming shape of every export,
//! so that memory holds two chunks of frames (the one being consumed and the next one being
//! made), not the whole animation.
//!
//! A chunk is twice as many items as rayon has threads, enough to keep every thread busy while a
//! slow frame finishes, and no more than [`CHUNK_BYTES`] of them, so that a chunk of huge frames
//! (`--size 16384x16384` is a GiB a frame) is one frame at a time.

use crate::error::Result;
use rayon::prelude::*;

/// At most this many bytes of items in one chunk (but always one item): two chunks are in
/// memory at a time.
const CHUNK_BYTES: usize = 128 << 20;

/// Items per chunk when each takes `item_bytes` (0 for small ones): twice the number of rayon
/// threads, fewer when that would pass [`CHUNK_BYTES`].
pub(crate) fn chunk_len(item_bytes: usize) -> usize {
    let by_threads = 2 * rayon::current_num_threads().max(1);
    match item_bytes {
        0 => by_threads,
        b => by_threads.min(CHUNK_BYTES / b).max(1),
    }
}

/// `make(item)` for every item, computed in parallel `chunk` items at a time (see
/// [`chunk_len`]) and handed to `sink` in the items' order; stops at the first error (of
/// `make`, in order, or of `sink`).
///
/// The next chunk is made on rayon's threads while `sink` takes the current one on the
/// calling thread, so a sink that does serial work (comparing a frame with the last, writing
/// it out) does not leave the cores idle. At most two chunks are in memory at a time.
pub(crate) fn in_order<I: Sync, T: Send>(
    items: &[I],
    chunk: usize,
    make: impl Fn(&I) -> Result<T> + Sync,
    mut sink: impl FnMut(T) -> Result<()>,
) -> Result<()> {
    let make_chunk = |c: &[I]| -> Vec<Result<T>> { c.par_iter().map(&make).collect() };
    let mut chunks = items.chunks(chunk.max(1));
    let mut ready = chunks.next().map(make_chunk);
    while let Some(made) = ready.take() {
        let next = chunks.next();
        let mut upcoming = None;
        let sunk = rayon::in_place_scope(|s| {
            if let Some(c) = next {
                s.spawn(|_| upcoming = Some(make_chunk(c)));
            }
            made.into_iter().try_for_each(|m| sink(m?))
        });
        sunk?;
        ready = upcoming;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_arrive_in_order_and_errors_stop_the_run() {
        let items: Vec<usize> = (0..100).collect();
        let mut seen = Vec::new();
        in_order(
            &items,
            chunk_len(0),
            |&i| Ok(i * 2),
            |x| {
                seen.push(x);
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(seen, (0..100).map(|i| i * 2).collect::<Vec<_>>());
        let mut n = 0;
        let r = in_order(
            &items,
            3,
            |&i| {
                if i == 50 {
                    Err(crate::Error::internal("boom"))
                } else {
                    Ok(i)
                }
            },
            |_| {
                n += 1;
                Ok(())
            },
        );
        assert!(r.is_err());
        assert_eq!(n, 50, "every item before the one that failed, none after");
        assert_eq!(chunk_len(1 << 30), 1);
        assert_eq!(chunk_len(0), chunk_len(1));
    }
}
