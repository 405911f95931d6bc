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
