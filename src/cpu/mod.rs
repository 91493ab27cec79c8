//! The CPU backend: strand-major SIMD blocks, a per-simulation worker pool, and the step
//! pipeline. It is also the reference the GPU backend is tested against.

mod aligned_rows;
pub(crate) mod avx2;
pub mod bridges;
pub mod cohesion;
pub mod denormals;
mod engine;
mod follower_output;
mod followers;
mod guide_columns;
pub mod held;
mod held_rows;
pub mod kernel;
pub mod layout;
pub mod output;
pub(crate) mod piles;
pub mod pool;
mod prefetch;
mod roots;
mod settle;
mod slot_spans;
pub mod step;
#[cfg(target_arch = "x86_64")]
mod transpose;
mod volume;
pub mod water;
