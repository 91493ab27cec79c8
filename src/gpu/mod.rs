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
