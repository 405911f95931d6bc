//! Data parallelism behind the `parallel` feature.
//!
//! With the feature on (the default) this is rayon: `par_iter()` over slices and
//! [`join`] of two closures run on rayon's pool. With it off the same calls run
//! sequentially on the calling thread, in order, so the library builds without rayon and
//! gives the same results (every parallel site in the crate collects in input order).

#[cfg(feature = "parallel")]
pub(crate) use rayon::join;

/// Runs `a` then `b` on the calling thread (the `parallel` feature is off).
#[cfg(not(feature = "parallel"))]
pub(crate) fn join<A, B, RA, RB>(a: A, b: B) -> (RA, RB)
where
    A: FnOnce() -> RA,
    B: FnOnce() -> RB,
{
    (a(), b())
}

/// Items a [`pipeline`]'s producer may have sent ahead of its consumer.
#[cfg(feature = "parallel")]
const PIPELINE_AHEAD: usize = 2;

/// Runs `produce` on the calling thread and `consume` on every item it sends, in the order
/// sent: on a thread of its own beside the producer when `threaded` (and the `parallel`
/// feature is on, and the thread can be started), else on the calling thread as each item
/// is sent. Sending an item gives back one the consumer is done with, when there is one, for
/// the producer to reuse (its buffers stay warm in cache, no fresh pages). Returns what
/// `produce` returns and the consumer's state `state`.
///
/// A producer that gets ahead of its consumer by `PIPELINE_AHEAD` (2) items waits, so the
/// items in flight are bounded. A panic of the consumer is raised again here.
pub(crate) fn pipeline<T, S, R>(
    threaded: bool,
    state: S,
    consume: impl FnMut(&mut S, &mut T) + Send,
    produce: impl FnOnce(&mut dyn FnMut(T) -> Option<T>) -> R,
) -> (R, S)
where
    T: Send,
    S: Send,
{
    // The consumer on a scoped thread, items handed over by channels.
    #[cfg(feature = "parallel")]
    if threaded {
        use std::sync::mpsc;
        // The consumer and its state move into the thread and come back when it ends, or are
        // taken back here unused when the thread cannot be started.
        let slot = std::sync::Mutex::new(Some((state, consume)));
        let take = || slot.lock().ok().and_then(|mut s| s.take());
        return std::thread::scope(|scope| {
            let (full_tx, full_rx) = mpsc::sync_channel::<T>(PIPELINE_AHEAD);
            let (done_tx, done_rx) = mpsc::channel::<T>();
            let worker = std::thread::Builder::new().spawn_scoped(scope, move || {
                let (mut state, mut consume) = take()?;
                for mut item in full_rx {
                    consume(&mut state, &mut item);
                    // The producer may have stopped listening: the item is then dropped.
                    let _ = done_tx.send(item);
                }
                Some(state)
            });
            let Ok(worker) = worker else {
                let (state, consume) = take().expect("a consumer whose thread did not start");
                return sequential_pipeline(state, consume, produce);
            };
            let r = produce(&mut |item| {
                // A consumer that panicked no longer receives: its panic is raised below.
                let _ = full_tx.send(item);
                done_rx.try_recv().ok()
            });
            drop(full_tx);
            match worker.join() {
                Ok(Some(state)) => (r, state),
                Ok(None) => unreachable!("a started consumer thread takes its state first"),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        });
    }
    let _ = threaded;
    sequential_pipeline(state, consume, produce)
}

/// [`pipeline`] on the calling thread.
fn sequential_pipeline<T, S, R>(
    mut state: S,
    mut consume: impl FnMut(&mut S, &mut T),
    produce: impl FnOnce(&mut dyn FnMut(T) -> Option<T>) -> R,
) -> (R, S) {
    let r = produce(&mut |mut item| {
        consume(&mut state, &mut item);
        Some(item)
    });
    (r, state)
}

/// `use crate::par::prelude::*;` in place of `use rayon::prelude::*;`.
pub(crate) mod prelude {
    #[cfg(feature = "parallel")]
    pub(crate) use rayon::prelude::*;

    #[cfg(not(feature = "parallel"))]
    pub(crate) use super::sequential::ParIter;
}

/// The sequential stand-in for rayon's `par_iter()`.
#[cfg(not(feature = "parallel"))]
mod sequential {
    /// `par_iter()` on a slice: the slice's own iterator.
    pub(crate) trait ParIter<T> {
        /// Iterates the items in order on the calling thread.
        fn par_iter(&self) -> std::slice::Iter<'_, T>;
    }

    impl<T> ParIter<T> for [T] {
        fn par_iter(&self) -> std::slice::Iter<'_, T> {
            self.iter()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::pipeline;

    /// Items reach the consumer in the order sent, on either route, and the buffers come
    /// back for reuse.
    #[test]
    fn pipeline_keeps_the_order_and_gives_buffers_back() {
        for threaded in [false, true] {
            let ((reused, sent), (got, emptied)) = pipeline(
                threaded,
                (Vec::new(), 0usize),
                |(got, emptied): &mut (Vec<u32>, usize), item: &mut Vec<u32>| {
                    got.append(item);
                    *emptied += 1;
                },
                |send| {
                    let mut reused = 0;
                    let mut buf = Vec::new();
                    for k in 0..1000u32 {
                        buf.push(k);
                        if buf.len() == 7 {
                            buf = match send(std::mem::take(&mut buf)) {
                                Some(b) => {
                                    assert!(b.is_empty(), "a buffer given back is consumed");
                                    reused += 1;
                                    b
                                }
                                None => Vec::new(),
                            };
                        }
                    }
                    send(buf);
                    (reused, 1000 / 7 + 1)
                },
            );
            assert_eq!(got, (0..1000).collect::<Vec<_>>(), "threaded {threaded}");
            assert_eq!(emptied, sent);
            // The sequential route gives every buffer back; the threaded one those done.
            assert!(reused < sent);
            if !threaded {
                assert_eq!(reused, sent - 1);
            }
        }
    }

    /// A consumer's panic is raised on the calling thread.
    #[test]
    fn pipeline_raises_the_consumers_panic() {
        for threaded in [false, true] {
            let r = std::panic::catch_unwind(|| {
                pipeline(
                    threaded,
                    0u32,
                    |n: &mut u32, item: &mut u32| {
                        *n += *item;
                        assert!(*n < 10, "consumer fails on purpose");
                    },
                    |send| {
                        for _ in 0..100 {
                            send(1);
                        }
                    },
                )
            });
            assert!(r.is_err(), "threaded {threaded}");
        }
    }
}
