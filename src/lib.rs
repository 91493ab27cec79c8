//! # wethair
//!
//! Real-time wet hair for engines. Each strand is a chain of mass points joined by
//! spring-dampers to neighbours i+1 (stretch) and i+2 (bend); roots follow the head. Water
//! particles pull nearby hair points toward them (Nishihama & Tokoi's eq. 2), so wet strands
//! clump into bundles; a hashed uniform grid finds the neighbours.
//!
//! The crate is built as a C-ABI library (`include/wethair.h`, see [`ffi`]) and as an rlib
//! whose Rust API is [`Simulation`]. The module map is in `ARCHITECTURE.md`.
//!
//! ```
//! use wethair::{groom::paper_scene, SimParams, Simulation};
//! let groom = paper_scene(100, 6).unwrap();
//! let mut sim = Simulation::new(&groom, SimParams::paper_scene_with_head()).unwrap();
//! sim.add_water(&[glam::Vec3::new(0.0, 0.0, 0.2)], &[]).unwrap();
//! sim.step(1.0 / 60.0).unwrap();
//! assert_eq!(sim.stats().points, 600);
//! ```

#![warn(missing_docs)]
// Lane loops index several arrays with one `l in 0..W`: that is the shape LLVM vectorises.
#![allow(clippy::needless_range_loop)]

pub mod cpu;
pub mod emit;
pub mod engine;
pub mod error;
pub mod ffi;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod groom;
pub mod params;
pub mod physics;
pub mod plan;
pub mod reference;
pub mod scenes;
pub mod sim;
pub mod timers;

pub use emit::{Rain, Spray};
pub use engine::{PassTime, WaterLedger};
pub use error::{Error, Result};
pub use params::{
    Backend, FixedStep, GuideChoice, Guides, HeldWater, Integrator, MaterialParams, Readback, SimParams, SpringModel,
    SpringParams, VertexAttributes, Volume, WaterParams, Wind,
};
pub use physics::collide::Shape;
pub use physics::spring::DampingModel;
pub use sim::{Advance, BackendInfo, Energy, ErrorEstimate, Simulation, Stats};
