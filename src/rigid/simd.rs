//! The frame's loops compiled for the widest vector instructions the processor has, chosen when
//! the program runs (issue 16: a 100k-vertex frame within 3 ms).
//!
//! A release build targets the baseline of its architecture (SSE2 on x86-64), so the solve's
//! eight lanes and the rotations' polynomials run two `f64` at a time even where the processor
//! could run four. [`vectorized`] runs a closure through `pulp` (the dispatch faer itself uses),
//! which compiles it once per instruction set (AVX2 and plain code on x86-64) and picks the best
//! one the processor reports.
//!
//! **The bits do not change.** The kernels are written with separate multiplications and
//! additions, and Rust never fuses the two into one rounding (no `mul_add` here): wider
//! registers do the same IEEE operations, lane by lane, in the same order. So a frame has the
//! same bits on every processor; the tests run the kernels both ways and compare.
//!
//! Only code inlined into the closure gets the wider instructions: callers pass an
//! `#[inline(always)]` closure that calls `#[inline(always)]` kernels.

#[cfg(test)]
thread_local! {
    /// Set by [`scalar`]: [`vectorized`] runs plain code on this thread.
    static SCALAR: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f`, compiled for the widest instruction set of this processor (module docs).
#[inline(always)]
pub(super) fn vectorized<R>(f: impl FnOnce() -> R) -> R {
    /// `f` as pulp's operation: its body inlined into each instruction set's copy.
    struct Op<F>(F);
    impl<R, F: FnOnce() -> R> pulp::WithSimd for Op<F> {
        type Output = R;
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _: S) -> R {
            (self.0)()
        }
    }
    #[cfg(test)]
    if SCALAR.get() {
        return pulp::Arch::Scalar.dispatch(Op(f));
    }
    pulp::Arch::new().dispatch(Op(f))
}

/// Runs `f` with every [`vectorized`] call on this thread in plain code: the reference the
/// wide instructions must match bit for bit.
#[cfg(test)]
pub(super) fn scalar<R>(f: impl FnOnce() -> R) -> R {
    SCALAR.set(true);
    let r = f();
    SCALAR.set(false);
    r
}

/// Whether [`vectorized`] picks wider instructions than plain code on this processor (tests
/// say so when they compare a path with itself).
#[cfg(test)]
pub(super) fn widens() -> bool {
    !matches!(pulp::Arch::new(), pulp::Arch::Scalar)
}
