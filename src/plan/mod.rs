//! What both backends follow and neither owns: which passes a step runs, which integrator
//! runs them, the springs' rest lengths, the water's domain and the checks on particles a host
//! adds. The CPU backend runs this plan over strand blocks; the GPU backend writes its kernels
//! from it.

pub mod integrator;
pub mod passes;
pub mod springs;
pub mod water;

pub use integrator::resolve_integrator;
pub use passes::{has_bend, pass_list, Pass};
pub use springs::{point_springs, rest_lengths, PointSprings};
pub use water::{check_new_particles, WaterDomain};
