//! Sharing the host's Vulkan device: what to enable, creating a simulation on the host's
//! VkDevice, and handing out the vertex VkBuffer with its synchronisation.
//!
//! Vulkan handles cross as `void*` (dispatchable: VkInstance, VkPhysicalDevice, VkDevice) or
//! `uint64_t` (non-dispatchable: VkBuffer, VkSemaphore), so the header needs no `vulkan.h`.
//! Without the cargo feature `vulkan` every call here returns `WETHAIR_ERROR_UNSUPPORTED`.

use super::boundary::{Fail, WetHairResult};
use super::sim::WetHairSim;
use super::types::WetHairSimDesc;
use std::ffi::{c_char, c_void};

#[cfg(feature = "vulkan")]
use crate::gpu::vulkan::REQUIRED_API_VERSION;
/// Never reported: without the `vulkan` feature the call is refused first.
#[cfg(not(feature = "vulkan"))]
const REQUIRED_API_VERSION: u32 = 0;

/// Most extension names accepted in one list.
#[cfg(feature = "vulkan")]
const MAX_EXTENSIONS: u32 = 4096;

/// The host's Vulkan objects (`wethair_vulkan_device_default` fills it empty). wethair never
/// destroys any of them; they must outlive every simulation made on them.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairVulkanDevice {
    /// `sizeof(WetHairVulkanDevice)`.
    pub struct_size: u32,
    /// `VkApplicationInfo::apiVersion` the instance was created with: at least Vulkan 1.1 and
    /// the device's own version (capped at 1.3); the reported `min_api_version` always is.
    pub api_version: u32,
    /// The loader's `vkGetInstanceProcAddr` (`PFN_vkGetInstanceProcAddr` cast to `void*`).
    pub get_instance_proc_addr: *const c_void,
    /// `VkInstance`.
    pub instance: *mut c_void,
    /// `VkPhysicalDevice` the device is (or will be) created on.
    pub physical_device: *mut c_void,
    /// `VkDevice`; may be NULL for `wethair_vulkan_requirements_create`.
    pub device: *mut c_void,
    /// Queue family of the queue wethair submits to (wgpu needs a family with graphics and
    /// compute; family 0 on every driver it supports).
    pub queue_family_index: u32,
    /// Index of that queue within its family.
    pub queue_index: u32,
    /// Entries in `instance_extensions`.
    pub instance_extension_count: u32,
    /// Entries in `device_extensions`.
    pub device_extension_count: u32,
    /// Instance extensions the host enabled (`VkInstanceCreateInfo::ppEnabledExtensionNames`).
    pub instance_extensions: *const *const c_char,
    /// Device extensions the host enabled (`VkDeviceCreateInfo::ppEnabledExtensionNames`).
    pub device_extensions: *const *const c_char,
    /// The `VkDeviceCreateInfo` the device was created with, or the `VkPhysicalDeviceFeatures2`
    /// chain it enabled; read during the call only, to check that every required feature is
    /// on. NULL skips the check (for engines that do not expose it; the host then vouches).
    pub enabled_features: *const c_void,
    /// Locks the queue before wethair submits or waits on it; NULL when the host never uses
    /// the queue from another thread while calling wethair. Set both or neither.
    pub queue_lock: Option<unsafe extern "C" fn(user_data: *mut c_void)>,
    /// Unlocks the queue.
    pub queue_unlock: Option<unsafe extern "C" fn(user_data: *mut c_void)>,
    /// Passed to `queue_lock` and `queue_unlock`. The callbacks may be called from any thread
    /// that calls wethair on a simulation made on this device.
    pub queue_user_data: *mut c_void,
}

/// What the host's instance must have before it can share its device with wethair.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairVulkanInstanceRequirements {
    /// `sizeof(WetHairVulkanInstanceRequirements)`, set by the host before the call.
    pub struct_size: u32,
    /// The `apiVersion` to create the instance with (a `VK_MAKE_API_VERSION` value): Vulkan
    /// 1.3, which any 1.1 or later loader accepts whatever the device offers. An instance made
    /// with it and `extensions` is all a device-sharing simulation needs of the instance.
    pub min_api_version: u32,
    /// Entries in `extensions`.
    pub extension_count: u32,
    /// Instance extensions to enable (static strings).
    pub extensions: *const *const c_char,
}

/// What the host's device must have: extensions to enable, and a feature chain to pass as
/// `VkDeviceCreateInfo::pNext` (with `pEnabledFeatures` NULL). Hosts that enable features of
/// their own can instead OR `feature_names` into their structs.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairVulkanRequirementsInfo {
    /// `sizeof(WetHairVulkanRequirementsInfo)`, set by the host before the call.
    pub struct_size: u32,
    /// Entries in `device_extensions`.
    pub device_extension_count: u32,
    /// Device extensions to enable (swapchain is never among them: wethair does not present).
    pub device_extensions: *const *const c_char,
    /// A `const VkPhysicalDeviceFeatures2*` whose chain enables every feature wethair needs.
    pub features: *const c_void,
    /// Entries in `feature_names`.
    pub feature_count: u32,
    /// Reserved, 0.
    pub reserved: u32,
    /// The Vulkan feature members (`robustBufferAccess`, `timelineSemaphore`, ...) the chain
    /// sets, for logs and for hosts that merge them into their own structs.
    pub feature_names: *const *const c_char,
}

/// The vertex buffer as a Vulkan resource, and the frame's synchronisation. The buffer holds
/// the last step's vertices, strand after strand, `stride_bytes` apart. It was created with
/// vertex, storage and transfer-source usage and stays the same `VkBuffer` until the
/// simulation is destroyed (steps and resets keep it).
///
/// Synchronisation: wait on `ready_semaphore` (timeline) for `ready_value` before reading
/// (`VK_PIPELINE_STAGE_VERTEX_INPUT_BIT` or the stage that reads), and signal
/// `release_semaphore` (timeline) to `release_value` once those reads are submitted; the
/// next step's write waits for that signal. Both are wethair's semaphores, destroyed with the
/// simulation. A host that gets the buffer must signal the release before the next step's
/// work can run.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairVulkanBuffer {
    /// `sizeof(WetHairVulkanBuffer)`, set by the host before the call.
    pub struct_size: u32,
    /// Vertices in the buffer (every point of every strand).
    pub vertex_count: u32,
    /// `VkBuffer`.
    pub buffer: u64,
    /// Byte offset of the first vertex in `buffer`.
    pub offset: u64,
    /// Bytes of vertex data.
    pub size: u64,
    /// Bytes from one vertex to the next.
    pub stride_bytes: u32,
    /// Strands (`vertex_count` is their points' total).
    pub strand_count: u32,
    /// Byte offset of the position in a vertex, or -1.
    pub position_offset: i32,
    /// `VkFormat` of the position (`VK_FORMAT_R32G32B32_SFLOAT` = 106), 0 when absent.
    pub position_format: u32,
    /// Byte offset of the unit tangent, or -1.
    pub tangent_offset: i32,
    /// `VkFormat` of the tangent (106), 0 when absent.
    pub tangent_format: u32,
    /// Byte offset of the wetness (0..1), or -1.
    pub wetness_offset: i32,
    /// `VkFormat` of the wetness (`VK_FORMAT_R32_SFLOAT` = 100), 0 when absent.
    pub wetness_format: u32,
    /// Timeline `VkSemaphore` to wait on.
    pub ready_semaphore: u64,
    /// Value to wait for.
    pub ready_value: u64,
    /// Timeline `VkSemaphore` to signal when done reading.
    pub release_semaphore: u64,
    /// Value to signal.
    pub release_value: u64,
}

/// The water particles as Vulkan resources, for hosts that draw them from wethair's buffers
/// (drops, spray) with no copy: a vertex buffer of positions and a `VkDrawIndirectCommand`
/// whose `vertexCount` is the particles held. Both are written in the same submission as
/// the frame's vertices, so the frame's semaphores from `wethair_sim_get_vulkan_buffer`
/// cover them: wait for `ready_value` at `VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
/// VK_PIPELINE_STAGE_VERTEX_INPUT_BIT`. Draw with `vkCmdDrawIndirect(cmd, draw_buffer,
/// draw_offset, 1, 0)` as a point list. The buffers stay the same until the simulation is
/// destroyed.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairVulkanWater {
    /// `sizeof(WetHairVulkanWater)`, set by the host before the call.
    pub struct_size: u32,
    /// Most particles the buffer holds (the simulation's water capacity).
    pub capacity: u32,
    /// `VkBuffer` of positions, one per particle held, `stride_bytes` apart.
    pub buffer: u64,
    /// Byte offset of the first position in `buffer`.
    pub offset: u64,
    /// Bytes from one position to the next (16: xyz and w = 1).
    pub stride_bytes: u32,
    /// `VkFormat` of the position: `VK_FORMAT_R32G32B32A32_SFLOAT` (109); reading it as
    /// `VK_FORMAT_R32G32B32_SFLOAT` (106) gives xyz.
    pub position_format: u32,
    /// `VkBuffer` holding the `VkDrawIndirectCommand` (vertexCount, instanceCount = 1,
    /// firstVertex = 0, firstInstance = 0).
    pub draw_buffer: u64,
    /// Byte offset of the command in `draw_buffer`.
    pub draw_offset: u64,
}

/// Requirements for a host's physical device; create with `wethair_vulkan_requirements_create`.
pub struct WetHairVulkanRequirements {
    #[cfg(feature = "vulkan")]
    inner: crate::gpu::vulkan::Requirements,
    extension_ptrs: Vec<*const c_char>,
    name_ptrs: Vec<*const c_char>,
}

fn unsupported() -> Fail {
    Fail(
        WetHairResult::WETHAIR_ERROR_UNSUPPORTED,
        "this build has no Vulkan sharing (cargo feature `vulkan`)".into(),
    )
}

/// Fills `device` with NULL handles, empty lists and its `struct_size`. NULL is ignored.
///
/// # Safety
/// `device` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_vulkan_device_default(device: *mut WetHairVulkanDevice) {
    super::boundary::write_default(device);
}

impl WetHairVulkanDevice {
    /// NULL handles, empty lists, API version 0 and this struct's size.
    pub fn default_values() -> Self {
        WetHairVulkanDevice {
            struct_size: std::mem::size_of::<WetHairVulkanDevice>() as u32,
            api_version: 0,
            get_instance_proc_addr: std::ptr::null(),
            instance: std::ptr::null_mut(),
            physical_device: std::ptr::null_mut(),
            device: std::ptr::null_mut(),
            queue_family_index: 0,
            queue_index: 0,
            instance_extension_count: 0,
            device_extension_count: 0,
            instance_extensions: std::ptr::null(),
            device_extensions: std::ptr::null(),
            enabled_features: std::ptr::null(),
            queue_lock: None,
            queue_unlock: None,
            queue_user_data: std::ptr::null_mut(),
        }
    }
}

/// Names of static C strings, shareable between threads.
struct StaticNames([*const c_char; 1]);
// SAFETY: the pointers are to 'static string literals, never written.
unsafe impl Sync for StaticNames {}
static INSTANCE_EXTENSION_NAMES: StaticNames = StaticNames([c"VK_KHR_get_physical_device_properties2".as_ptr()]);

/// What the host's VkInstance must have: the lowest API version and the instance extensions.
/// Callable before any Vulkan object exists. The host sets `out->struct_size` first.
///
/// # Safety
/// `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_vulkan_get_instance_requirements(
    out: *mut WetHairVulkanInstanceRequirements,
) -> WetHairResult {
    boundary!({
        let out = check_out_size!(out, WetHairVulkanInstanceRequirements, "out");
        if !cfg!(feature = "vulkan") {
            return Err(unsupported());
        }
        out.write(WetHairVulkanInstanceRequirements {
            struct_size: std::mem::size_of::<WetHairVulkanInstanceRequirements>() as u32,
            min_api_version: REQUIRED_API_VERSION,
            extension_count: INSTANCE_EXTENSION_NAMES.0.len() as u32,
            extensions: INSTANCE_EXTENSION_NAMES.0.as_ptr(),
        });
        Ok(())
    })
}

/// Reads `count` extension names; NULL entries and a NULL array with a count are errors.
#[cfg(feature = "vulkan")]
unsafe fn read_names(p: *const *const c_char, count: u32, what: &str) -> Result<Vec<std::ffi::CString>, Fail> {
    if count == 0 {
        return Ok(Vec::new());
    }
    if count > MAX_EXTENSIONS {
        return Err(Fail(
            WetHairResult::WETHAIR_ERROR_CAPACITY,
            format!("{what}: {count} names exceed {MAX_EXTENSIONS}"),
        ));
    }
    if p.is_null() {
        return Err(super::boundary::null(what));
    }
    let mut out = Vec::with_capacity(count as usize);
    for i in 0..count as usize {
        let s = *p.add(i);
        if s.is_null() {
            return Err(Fail(
                WetHairResult::WETHAIR_ERROR_NULL_POINTER,
                format!("{what}[{i}] is NULL"),
            ));
        }
        out.push(std::ffi::CStr::from_ptr(s).to_owned());
    }
    Ok(out)
}

/// Checks a `WetHairVulkanDevice` and turns it into the Rust side's description.
#[cfg(feature = "vulkan")]
unsafe fn host_vulkan(d: &WetHairVulkanDevice, need_device: bool) -> Result<crate::gpu::vulkan::HostVulkan, Fail> {
    use ash::vk::{self, Handle};
    if d.get_instance_proc_addr.is_null() {
        return Err(super::boundary::null("host->get_instance_proc_addr"));
    }
    if d.instance.is_null() {
        return Err(super::boundary::null("host->instance"));
    }
    if d.physical_device.is_null() {
        return Err(super::boundary::null("host->physical_device"));
    }
    if need_device && d.device.is_null() {
        return Err(super::boundary::null("host->device"));
    }
    let queue_lock = match (d.queue_lock, d.queue_unlock) {
        (Some(lock), Some(unlock)) => Some(crate::gpu::vulkan::QueueLock {
            lock,
            unlock,
            user: d.queue_user_data,
        }),
        (None, None) => None,
        _ => {
            return Err(Fail(
                WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT,
                "host->queue_lock and host->queue_unlock must be set together".into(),
            ))
        }
    };
    // SAFETY: the host passes vkGetInstanceProcAddr as void*; the types agree.
    let gipa: vk::PFN_vkGetInstanceProcAddr = std::mem::transmute(d.get_instance_proc_addr);
    Ok(crate::gpu::vulkan::HostVulkan {
        get_instance_proc_addr: gipa,
        instance: vk::Instance::from_raw(d.instance as u64),
        physical_device: vk::PhysicalDevice::from_raw(d.physical_device as u64),
        device: vk::Device::from_raw(d.device as u64),
        queue_family: d.queue_family_index,
        queue_index: d.queue_index,
        api_version: d.api_version,
        instance_extensions: read_names(
            d.instance_extensions,
            d.instance_extension_count,
            "host->instance_extensions",
        )?,
        device_extensions: read_names(d.device_extensions, d.device_extension_count, "host->device_extensions")?,
        enabled_features: d.enabled_features,
        enabled_feature_names: None,
        queue_lock,
    })
}

/// Finds what wethair needs of a device on `host->physical_device` (`host->device` may be
/// NULL): device extensions and a feature chain for `VkDeviceCreateInfo`. Free with
/// `wethair_vulkan_requirements_destroy`; the info's pointers live as long as `*out`.
///
/// # Safety
/// `host` is filled by `wethair_vulkan_device_default` and then with live handles; `out` is
/// writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_vulkan_requirements_create(
    host: *const WetHairVulkanDevice,
    out: *mut *mut WetHairVulkanRequirements,
) -> WetHairResult {
    boundary!({
        let d = read_def!(host, WetHairVulkanDevice, "host");
        if out.is_null() {
            return Err(super::boundary::null("out"));
        }
        #[cfg(feature = "vulkan")]
        {
            let inner = crate::gpu::vulkan::requirements(&host_vulkan(&d, false)?)?;
            let extension_ptrs = inner.device_extensions.iter().map(|c| c.as_ptr()).collect();
            let name_ptrs = inner.feature_names.iter().map(|c| c.as_ptr()).collect();
            out.write(Box::into_raw(Box::new(WetHairVulkanRequirements {
                inner,
                extension_ptrs,
                name_ptrs,
            })));
            Ok(())
        }
        #[cfg(not(feature = "vulkan"))]
        {
            let _ = d;
            Err(unsupported())
        }
    })
}

/// Describes the requirements. The host sets `out->struct_size` first.
///
/// # Safety
/// `req` came from `wethair_vulkan_requirements_create`; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_vulkan_requirements_get_info(
    req: *const WetHairVulkanRequirements,
    out: *mut WetHairVulkanRequirementsInfo,
) -> WetHairResult {
    boundary!({
        let r = nonnull!(req, "req");
        let out = check_out_size!(out, WetHairVulkanRequirementsInfo, "out");
        #[cfg(feature = "vulkan")]
        let features = r.inner.features_chain();
        #[cfg(not(feature = "vulkan"))]
        let features = std::ptr::null();
        out.write(WetHairVulkanRequirementsInfo {
            struct_size: std::mem::size_of::<WetHairVulkanRequirementsInfo>() as u32,
            device_extension_count: r.extension_ptrs.len() as u32,
            device_extensions: r.extension_ptrs.as_ptr(),
            features,
            feature_count: r.name_ptrs.len() as u32,
            reserved: 0,
            feature_names: r.name_ptrs.as_ptr(),
        });
        Ok(())
    })
}

/// Frees requirements. NULL is ignored.
///
/// # Safety
/// `req` came from `wethair_vulkan_requirements_create` and is not used again.
#[no_mangle]
pub unsafe extern "C" fn wethair_vulkan_requirements_destroy(req: *mut WetHairVulkanRequirements) {
    if !req.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| drop(Box::from_raw(req))));
    }
}

/// Creates a simulation whose GPU backend runs on the host's VkDevice. `desc->backend` must be
/// `WETHAIR_BACKEND_AUTO` or `WETHAIR_BACKEND_GPU`. Fails with `WETHAIR_ERROR_UNSUPPORTED`,
/// naming what is missing, when the host's instance or device lacks a required extension or
/// (when `host->enabled_features` is set) feature. Destroying the simulation leaves the host's
/// objects alive and usable.
///
/// # Safety
/// `desc` and `host` are filled by their `_default()` functions, `host` with live handles; `out`
/// is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_create_vulkan(
    desc: *const WetHairSimDesc,
    host: *const WetHairVulkanDevice,
    out: *mut *mut WetHairSim,
) -> WetHairResult {
    boundary!({
        let sd = read_def!(desc, WetHairSimDesc, "desc");
        let d = read_def!(host, WetHairVulkanDevice, "host");
        if out.is_null() {
            return Err(super::boundary::null("out"));
        }
        let groom: &super::groom::WetHairGroom = nonnull!(sd.groom, "desc->groom");
        let params = sd.params()?;
        #[cfg(feature = "vulkan")]
        {
            let hv = host_vulkan(&d, true)?;
            let sim = crate::sim::Simulation::new_on_vulkan(&groom.0, params, &hv)?;
            out.write(Box::into_raw(Box::new(WetHairSim(sim))));
            Ok(())
        }
        #[cfg(not(feature = "vulkan"))]
        {
            let _ = (d, groom, params);
            Err(unsupported())
        }
    })
}

/// Hands out the vertex buffer holding the last step's vertices, with its layout and the
/// semaphore values of this frame (see `WetHairVulkanBuffer`). Only for simulations made by
/// `wethair_sim_create_vulkan` (else `WETHAIR_ERROR_UNSUPPORTED`). The host sets
/// `out->struct_size` first. A failed step is never written to the buffer: it keeps the last
/// good frame, and the failure is reported here once a read has seen it. Called again with no
/// step in between (a paused host) it hands out the same frame and the same values: wait and
/// signal each `release_value` once (a timeline semaphore only moves forward).
///
/// # Safety
/// `sim` is valid; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_get_vulkan_buffer(
    sim: *mut WetHairSim,
    out: *mut WetHairVulkanBuffer,
) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        let out = check_out_size!(out, WetHairVulkanBuffer, "out");
        #[cfg(feature = "vulkan")]
        {
            use crate::params::VertexAttributes;
            let a = s.0.attributes();
            let f = s.0.vulkan_frame()?;
            let off = |bit| a.offset(bit).map_or(-1, |o| (o * 4) as i32);
            let fmt = |bit, vk_format| if a.offset(bit).is_some() { vk_format } else { 0 };
            out.write(WetHairVulkanBuffer {
                struct_size: std::mem::size_of::<WetHairVulkanBuffer>() as u32,
                vertex_count: s.0.vertex_count() as u32,
                buffer: f.buffer,
                offset: 0,
                size: f.size,
                stride_bytes: (a.stride() * 4) as u32,
                strand_count: s.0.stats_counts().0,
                position_offset: off(VertexAttributes::POSITION),
                position_format: fmt(VertexAttributes::POSITION, 106),
                tangent_offset: off(VertexAttributes::TANGENT),
                tangent_format: fmt(VertexAttributes::TANGENT, 106),
                wetness_offset: off(VertexAttributes::WETNESS),
                wetness_format: fmt(VertexAttributes::WETNESS, 100),
                ready_semaphore: f.ready_semaphore,
                ready_value: f.ready_value,
                release_semaphore: f.release_semaphore,
                release_value: f.release_value,
            });
            Ok(())
        }
        #[cfg(not(feature = "vulkan"))]
        {
            let _ = (s, out);
            Err(unsupported())
        }
    })
}

/// Hands out the water particles' positions and indirect-draw arguments as Vulkan buffers
/// (see `WetHairVulkanWater`). Only for simulations made by `wethair_sim_create_vulkan` (else
/// `WETHAIR_ERROR_UNSUPPORTED`). The first call creates the two buffers (capacity x 16 bytes
/// and 16 bytes; nothing of the kind exists until a host asks) and writes the current
/// particles into them, waiting for the device once; from then on every frame's vertex write
/// also writes them. Call it after `wethair_sim_get_vulkan_buffer` for the frame. The host
/// sets `out->struct_size` first.
///
/// # Safety
/// `sim` is valid; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_get_vulkan_water(
    sim: *mut WetHairSim,
    out: *mut WetHairVulkanWater,
) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        let out = check_out_size!(out, WetHairVulkanWater, "out");
        #[cfg(feature = "vulkan")]
        {
            let w = s.0.vulkan_water()?;
            out.write(WetHairVulkanWater {
                struct_size: std::mem::size_of::<WetHairVulkanWater>() as u32,
                capacity: w.capacity,
                buffer: w.buffer,
                offset: 0,
                stride_bytes: 16,
                position_format: 109,
                draw_buffer: w.draw_buffer,
                draw_offset: 0,
            });
            Ok(())
        }
        #[cfg(not(feature = "vulkan"))]
        {
            let _ = (s, out);
            Err(unsupported())
        }
    })
}
