//! Work written once over the kernels, run with the kernels of the active instruction set,
//! compiled for it.

use crate::simd::Isa;
use crate::simd::kernel::{Kernel, Portable};
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
use crate::simd::wasm;
#[cfg(target_arch = "x86_64")]
use crate::simd::x86;

/// Work written once over the kernels of any instruction set: a traversal, whose loop calls a
/// [`Kernel`] for what it does in lanes. [`run_with_active_kernels`] runs it with the active
/// set's kernels.
pub(crate) trait KernelJob {
    /// What the work gives.
    type Output;
    /// Does the work with the kernels of `K`. Marked `#[inline(always)]` in every
    /// implementation, so that each instruction set's copy of the work is compiled inside
    /// the function that enables the set, with the kernels inlined into it.
    fn run<K: Kernel>(self) -> Self::Output;
}

/// Runs `job` with the kernels of [`Isa::active`].
#[inline]
pub(crate) fn run_with_active_kernels<J: KernelJob>(job: J) -> J::Output {
    // SAFETY: `Isa::active` holds only an instruction set this machine has.
    unsafe { run_on(Isa::active(), job) }
}

/// Runs `job` with the kernels of `isa` (tests hold every set to the same answers); panics
/// for a set this machine lacks.
#[cfg(test)]
pub(crate) fn run_with<J: KernelJob>(isa: Isa, job: J) -> J::Output {
    assert!(isa.is_available(), "{isa:?} is not available here");
    // SAFETY: checked just above.
    unsafe { run_on(isa, job) }
}

/// Runs `job` with the kernels of `isa`, compiled for it.
///
/// # Safety
/// The machine must have `isa` ([`Isa::is_available`]).
#[inline(always)]
unsafe fn run_on<J: KernelJob>(isa: Isa, job: J) -> J::Output {
    #[cfg(target_arch = "x86_64")]
    match isa {
        // SAFETY: the caller promises the machine has the set.
        Isa::Avx512 => return unsafe { x86::run_avx512(job) },
        // SAFETY: as above.
        Isa::Avx2 => return unsafe { x86::run_avx2(job) },
        _ => {}
    }
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    if isa == Isa::Simd128 {
        return job.run::<wasm::Simd128>();
    }
    let _ = isa;
    job.run::<Portable>()
}
