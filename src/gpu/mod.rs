//! The GPU backend on wgpu compute (feature `gpu`). The passes in `shaders/*.wgsl` mirror the
//! CPU's pass by pass, in the same order and with the same names; the state stays on the
//! device and only explicit readbacks return to the host.

pub mod backend;
pub mod buffers;
pub mod device;
#[cfg(feature = "unity")]
pub mod intercept;
pub mod pipelines;
#[cfg(feature = "vulkan")]
pub mod vulkan;
pub mod wgsl;

pub use backend::GpuBackend;
pub use device::GpuDevice;

/// Why the GPU backend cannot run `p`, for what it does not have yet (`None`: it can, as far
/// as these go): drops that coalesce (`WaterParams::pile_cell` in the paper's model; with held
/// water both backends ignore it) run on the CPU backend only. `Backend::GPU` is refused with
/// this, and AUTO picks the CPU backend with it as the reason.
pub fn refuses(p: &crate::SimParams) -> Option<String> {
    p.coalesces()
        .then(|| "water pile_cell (drops that meet coalesce) runs on the CPU backend only for now".to_string())
}
