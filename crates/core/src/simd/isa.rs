//! The instruction sets the kernels are written for, which this machine has, and which one
//! traversal uses.

use std::sync::atomic::{AtomicU8, Ordering};

/// An instruction set the kernels are written for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Isa {
    /// Plain Rust, one lane at a time (what the compiler makes of it): every machine.
    Portable,
    /// x86-64 with AVX2 and FMA (Intel since 2013, AMD since 2015): 8 lanes of f32.
    Avx2,
    /// x86-64 with AVX-512 F and VL: the AVX2 kernels compiled with AVX-512 enabled (its
    /// mask registers where the compiler uses them).
    Avx512,
    /// WebAssembly `simd128`: 4 lanes, fixed when the module is compiled.
    Simd128,
}

impl Isa {
    /// Every instruction set, in order of preference (best last).
    pub const ALL: [Isa; 4] = [Isa::Portable, Isa::Simd128, Isa::Avx2, Isa::Avx512];

    /// The name the CLI takes: `portable`, `avx2`, `avx512`, `simd128`.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Portable => "portable",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
            Isa::Simd128 => "simd128",
        }
    }

    /// The set named `name`.
    pub fn parse(name: &str) -> Option<Isa> {
        Isa::ALL.into_iter().find(|isa| isa.name() == name)
    }

    /// Whether this machine (or this WebAssembly module) can run the set.
    pub fn is_available(self) -> bool {
        match self {
            Isa::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => {
                Isa::Avx2.is_available()
                    && std::arch::is_x86_feature_detected!("avx512f")
                    && std::arch::is_x86_feature_detected!("avx512vl")
            }
            #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
            Isa::Simd128 => true,
            _ => false,
        }
    }

    /// The best set this machine has.
    pub fn detect() -> Isa {
        Isa::ALL
            .into_iter()
            .rev()
            .find(|isa| isa.is_available())
            .unwrap_or(Isa::Portable)
    }

    fn code(self) -> u8 {
        match self {
            Isa::Portable => 1,
            Isa::Avx2 => 2,
            Isa::Avx512 => 3,
            Isa::Simd128 => 4,
        }
    }

    /// The set traversal uses: the best one detected, unless [`Isa::set_active`] chose another.
    #[inline]
    pub fn active() -> Isa {
        match ACTIVE.load(Ordering::Relaxed) {
            1 => Isa::Portable,
            2 => Isa::Avx2,
            3 => Isa::Avx512,
            4 => Isa::Simd128,
            _ => {
                let detected = Isa::detect();
                ACTIVE.store(detected.code(), Ordering::Relaxed);
                detected
            }
        }
    }

    /// Makes traversal use `isa` from now on (to measure one set against another, or test
    /// one); refused for a set this machine cannot run.
    pub fn set_active(isa: Isa) -> Result<(), IsaError> {
        if !isa.is_available() {
            return Err(IsaError::Unavailable {
                isa,
                detected: Isa::detect(),
            });
        }
        ACTIVE.store(isa.code(), Ordering::Relaxed);
        Ok(())
    }
}

/// The instruction set in use: 0 until first asked.
static ACTIVE: AtomicU8 = AtomicU8::new(0);

/// An instruction set this machine does not have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum IsaError {
    /// Asked for a set the processor lacks.
    #[error("this machine cannot run {} kernels (the best it has is {})", isa.name(), detected.name())]
    Unavailable {
        /// What was asked for.
        isa: Isa,
        /// The best it has.
        detected: Isa,
    },
}
