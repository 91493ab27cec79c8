//! Every integration test, in one binary: each file in `tests/` is a module here. A test
//! binary is linked with thin LTO against the whole dependency graph (wgpu, naga), and one per
//! file made the link most of CI's time. Run one file's tests with a filter, e.g.
//! `cargo test --release --test all estimate::`.

mod common;

mod architecture;
mod collider_frames;
mod emit;
mod estimate;
mod extreme;
mod ffi;
mod ffi_wet;
mod fixed_step;
mod gpu;
mod grid;
mod guide_roots;
mod guide_water;
mod guides;
mod hardening;
mod header;
mod held_water;
mod integrators;
mod loaders;
mod material;
mod output;
mod passes;
mod physics;
mod piles;
mod reference;
mod roots;
mod sdf;
mod shaders;
mod standalone;
mod unity;
mod volume;
mod wet_groom;
mod wet_laws;
mod wet_model;
