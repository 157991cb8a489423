//! Frames made in parallel chunks and consumed in order: the streaming shape of every export,
//! so that memory holds one chunk of frames, not the whole animation.
//!
//! A chunk is twice as many items as rayon has threads: enough to keep every thread busy
//! while a slow frame finishes, few enough that a chunk of 16-megapixel frames stays small.

use crate::error::Result;
use rayon::prelude::*;

/// Items per chunk: twice the number of rayon threads.
pub(crate) fn chunk_len() -> usize {
    2 * rayon::current_num_threads().max(1)
}

/// `make(item)` for every item, computed in parallel one chunk at a time and handed to `sink`
/// in the items' order; stops at the first error (of `make`, in order, or of `sink`).
pub(crate) fn in_order<I: Sync, T: Send>(
    items: &[I],
    make: impl Fn(&I) -> Result<T> + Sync,
    mut sink: impl FnMut(T) -> Result<()>,
) -> Result<()> {
    for chunk in items.chunks(chunk_len()) {
        let made: Vec<Result<T>> = chunk.par_iter().map(&make).collect();
        for m in made {
            sink(m?)?;
        }
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
        assert_eq!(n, 50);
    }
}
