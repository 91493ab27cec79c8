//! Running a CPU pass compiled for AVX2 where the machine has it. Code is compiled for the
//! target features of the function it is inlined into, and a closure run on the worker pool
//! is compiled for the baseline (SSE2), where eight-lane loops run four lanes at a time or
//! one. So each hot pass runs its `#[inline(always)]` body through [`run_avx2_or_base`] (or
//! a pool entry made by [`avx2_or_base!`], which calls it): through a wrapper compiled for
//! AVX2 when the simulation found AVX2 at create ([`cpu_has_avx2`]), else as it is. Both
//! builds give the same bits: neither contracts a multiply and an add.

/// Whether this CPU runs AVX2 (checked once per simulation).
pub(crate) fn cpu_has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// `avx2_or_base!(/// docs\n fn best(job: &Job, range: Range<usize>) => body);` defines `best`,
/// which runs `body(job, range)` compiled for AVX2 when `job.avx2` is set (a flag taken from
/// [`cpu_has_avx2`]), else compiled for the baseline: [`run_avx2_or_base`] as a named pool
/// entry. Used from modules of `cpu/`.
macro_rules! avx2_or_base {
    ($(#[$doc:meta])* fn $best:ident($job:ident: &$Job:ty, $range:ident: $Range:ty) => $body:ident) => {
        $(#[$doc])*
        fn $best($job: &$Job, $range: $Range) {
            super::avx2::run_avx2_or_base(
                $job.avx2,
                #[inline(always)]
                || $body($job, $range),
            )
        }
    };
}
pub(crate) use avx2_or_base;

/// Runs `f` compiled for AVX2 when `avx2` (a flag taken from [`cpu_has_avx2`]), else as it
/// is: for a pass's per-task closure, which the pool would otherwise run compiled for the
/// baseline. Mark the closure `#[inline(always)]`: inlined into the wrapper it takes the
/// wrapper's features (left out of line, as LLVM leaves a closure called from both builds,
/// it stays a baseline function). Both builds give the same bits: neither contracts a
/// multiply and an add.
#[inline(always)]
pub(crate) fn run_avx2_or_base<R>(avx2: bool, f: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        #[target_feature(enable = "avx2")]
        unsafe fn run<R>(f: impl FnOnce() -> R) -> R {
            f()
        }
        // SAFETY: `avx2` comes from `cpu_has_avx2` (`is_x86_feature_detected!("avx2")`).
        return unsafe { run(f) };
    }
    let _ = avx2;
    f()
}
