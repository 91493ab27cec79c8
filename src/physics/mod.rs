//! The laws, each written once: springs (eq. 1), adhesion (eq. 2), the uniform grid (eqs. 4-5),
//! colliders (analytic and signed distance fields), skinned roots, hair-hair volume, the integrator, and the clumping measure. The CPU backend runs them over strand
//! blocks; nothing here knows about threads or the C ABI.

pub mod absorb;
pub mod adhesion;
#[cfg(target_arch = "x86_64")]
pub mod adhesion_avx2;
pub mod bdf2;
pub mod bundles;
pub mod clumping;
pub mod collide;
pub mod counting_sort;
pub mod follow;
pub mod follow_lanes;
pub mod follow_roots;
pub mod followers;
pub mod frames;
pub mod grid;
pub mod hash_grid;
pub mod hash_marks;
pub mod head;
pub mod implicit;
pub mod integrate;
pub mod lanes;
#[cfg(target_arch = "x86_64")]
pub mod lanes_avx2;
pub mod morton;
pub mod per_length;
pub mod pull_limit;
pub mod roots;
pub mod rounding;
pub mod sdf;
pub mod spring;
pub mod trilinear;
pub mod volume;
pub mod wet;
pub mod xpbd;
