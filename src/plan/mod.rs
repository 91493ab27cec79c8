//! What both backends follow and neither owns: which passes a step runs, which integrator
//! runs them, the springs' rest lengths, the water's domain and the checks on particles a host
//! adds. The CPU backend runs this plan over strand blocks; the GPU backend writes its kernels
//! from it.

pub mod integrator;
pub mod passes;
pub mod rest;
pub mod water;

pub use integrator::resolve_integrator;
pub use passes::{has_bend, pass_list, Pass};
pub use rest::rest_lengths;
pub use water::{check_new_particles, WaterDomain};
