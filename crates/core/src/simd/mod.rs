//! The SIMD kernels of the wide BVH's hot path and their run-time dispatch: the one module of
//! the core allowed `unsafe`.
//!
//! It sits below the traversals and knows nothing of trees. Its floors, top to bottom:
//! - the dispatch (`isa.rs`, `dispatch.rs`): [`Isa::detect`] asks the processor once which instruction sets
//!   it has; `run_with_active_kernels` runs a `KernelJob` (a traversal, written once over
//!   a `Kernel`) compiled once per set, each copy inside a `#[target_feature]` function, so
//!   the kernels inline into the traversal's loop;
//! - the kernels (`kernel.rs`): what a wide traversal needs done in lanes (a node's child
//!   boxes, a block of four triangles, one box against a packet's rays), the portable
//!   reference (`Portable`), and each instruction set's `Kernel` over it;
//! - the lanes (`lanes.rs`): those operations written once over any set's registers, and the
//!   registers of x86-64 (`x86.rs`: SSE, AVX2, AVX-512) and WebAssembly (`wasm.rs`: simd128).
//!
//! `unsafe` is needed for three things only, all here:
//! - calling a `#[target_feature]` function, which is sound only on a processor that has the
//!   feature: every such call is behind [`Isa::active`], which only ever holds a detected set;
//! - loading and storing SIMD registers through pointers, each into a slice indexed first (so
//!   the lanes loaded are inside it); and x86 intrinsics outside `#[target_feature]`
//!   functions, in the lanes, which run only inside such functions;
//! - the prefetch hint (`prefetch_lines`), which never faults whatever its address.
//!
//! Every kernel does the arithmetic of the portable code in the same order, with the same NaN
//! rules (`max_ps(a, b)` is `a > b ? a : b`, which ignores a NaN `a`, like the slab module's
//! reductions), and no fused multiply-adds, so its results are bit for bit the portable ones;
//! the tests (`tests.rs`) hold every kernel to that on random and extreme inputs.
//!
//! In the browser the kernels are WebAssembly `simd128`, chosen when the module is compiled
//! (WebAssembly has no run-time detection; every browser of the last years has it).

#![allow(unsafe_code)]

mod dispatch;
mod isa;
mod kernel;
mod lanes;
#[cfg(test)]
mod tests;
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod wasm;
#[cfg(target_arch = "x86_64")]
mod x86;

pub use kernel::MAX_PACKET;
pub(crate) use kernel::{BoxAgainstRays, ChildTests, Kernel, LANES, NodeLanes, PacketLanes};

#[cfg(test)]
pub(crate) use dispatch::run_with;
pub(crate) use dispatch::{KernelJob, run_with_active_kernels};
pub use isa::{Isa, IsaError};
pub(crate) use kernel::prefetch_lines;
