//! Every struct that leads with `struct_size`, with the size of its first released layout
//! (what a host compiled against that header passes), and the defaults that fields past an
//! older host's size take. `tests/abi/` compiles a C program against the saved 0.1.0 header
//! and drives the library with these sizes.

use super::boundary::{DefStruct, SizedStruct};
use super::types::{
    WetHairAdvance, WetHairBackendInfo, WetHairGroomDesc, WetHairLoadDesc, WetHairSimDesc, WetHairStats,
    WetHairVertexLayout,
};
use super::unity::WetHairUnityStatus;
use super::vulkan::{
    WetHairVulkanBuffer, WetHairVulkanDevice, WetHairVulkanInstanceRequirements, WetHairVulkanRequirementsInfo,
    WetHairVulkanWater,
};

/// `sized!(Type = first size, ...)`: the [`SizedStruct`] impls, one line per struct.
macro_rules! sized {
    ($($ty:ty = $first:expr),+ $(,)?) => {
        $(
            // SAFETY: each is #[repr(C)], starts with `struct_size: u32`, and holds only
            // integers, floats, nullable pointers, optional function pointers and char arrays.
            unsafe impl SizedStruct for $ty {
                const FIRST_SIZE: usize = $first;
            }
        )+
        /// Each struct's name, first released size and size now (`tests/ffi.rs`).
        pub fn struct_sizes() -> Vec<(&'static str, usize, usize)> {
            vec![$((stringify!($ty), $first, std::mem::size_of::<$ty>())),+]
        }
    };
}

sized!(
    // 0.1.0
    WetHairGroomDesc = 56,
    WetHairSimDesc = 128,
    WetHairVertexLayout = 28,
    WetHairStats = 56,
    WetHairBackendInfo = 392,
    WetHairUnityStatus = 280,
    WetHairVulkanDevice = 104,
    WetHairVulkanInstanceRequirements = 24,
    WetHairVulkanRequirementsInfo = 40,
    WetHairVulkanBuffer = 96,
    WetHairVulkanWater = 48,
    // 0.2.0 (WetHairStats grew to 104 bytes: clumping_along, the water ledger;
    // WetHairSimDesc to 216: spring_model, material, held_water, wind)
    WetHairLoadDesc = 32,
    // 0.3.0: WetHairSimDesc grew to 232 (error_estimate_stride, tolerance, max_substeps),
    // WetHairStats to 120 (error_estimate, error_estimate_max, substeps)
    // 0.4.0 (WetHairSimDesc grew to 296: fixed_step, max_frame_time, interpolate, sdfs,
    // sdf_count, skinned_roots, root_teleport_distance, volume)
    // 0.5.0: WetHairSimDesc grew to 328 (guides)
    // 0.6.0: WetHairSimDesc grew to 336 (held_water_free_ratio)
    // 0.7.0: WetHairSimDesc grew to 344 (held_water_flow_length)
    // 0.8.0: WetHairSimDesc grew to 360 (air_drag_length, water_adhesion_length)
    // 0.9.0: WetHairSimDesc grew to 368 (water_pile_cell)
    // 0.10.0: WetHairSimDesc grew to 376 (collider_frames)
    WetHairAdvance = 16,
);

impl DefStruct for WetHairSimDesc {
    fn defaults() -> Self {
        WetHairSimDesc::default_values()
    }
}

impl DefStruct for WetHairGroomDesc {
    fn defaults() -> Self {
        WetHairGroomDesc::default_values()
    }
}

impl DefStruct for WetHairLoadDesc {
    fn defaults() -> Self {
        WetHairLoadDesc::default_values()
    }
}

impl DefStruct for WetHairVulkanDevice {
    fn defaults() -> Self {
        WetHairVulkanDevice::default_values()
    }
}
