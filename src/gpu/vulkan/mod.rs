//! Running on the host's own VkDevice (feature `vulkan`): what the host must enable, opening
//! wgpu on its handles through wgpu-hal, and the two timeline semaphores that order the
//! host's draws against our writes of the vertex buffer.
//!
//! Nothing here owns the host's objects: wgpu-hal gets drop callbacks that do nothing, so the
//! host's VkInstance and VkDevice outlive every simulation made on them.

use super::device::{descriptor, wanted, GpuDevice};
use crate::error::{Error, Result};
use ash::vk;
use std::ffi::{c_void, CStr, CString};
use std::sync::{Arc, Mutex};
use wgpu::hal::api::Vulkan;
use wgpu::hal::vulkan as hv;

mod sync;
pub use sync::{raw_buffer, raw_semaphore, SharedFrame, SharedSync, SharedWater};

/// The oldest Vulkan API version wethair runs on (wgpu-hal needs 1.1's core features).
pub const MIN_API_VERSION: u32 = vk::API_VERSION_1_1;

/// The `apiVersion` wethair asks a host's instance to be created with: wgpu uses its device's
/// Vulkan version up to 1.3, which Vulkan allows only up to the instance's apiVersion, so an
/// instance made with 1.3 suits every device (a 1.1 or later loader accepts it whatever the
/// device offers). What `wethair_vulkan_get_instance_requirements` reports.
pub const REQUIRED_API_VERSION: u32 = vk::API_VERSION_1_3;

/// Instance-level entry points wgpu-hal calls on the host's instance; each must resolve
/// through the host's `vkGetInstanceProcAddr` (checked by name before any is called).
const INSTANCE_ENTRIES: [&CStr; 11] = [
    c"vkGetDeviceProcAddr",
    c"vkEnumeratePhysicalDevices",
    c"vkGetPhysicalDeviceProperties",
    c"vkGetPhysicalDeviceProperties2",
    c"vkGetPhysicalDeviceFeatures",
    c"vkGetPhysicalDeviceFeatures2",
    c"vkGetPhysicalDeviceQueueFamilyProperties",
    c"vkGetPhysicalDeviceMemoryProperties",
    c"vkGetPhysicalDeviceFormatProperties",
    c"vkEnumerateDeviceExtensionProperties",
    c"vkCreateDevice",
];

/// The first entry wethair needs that the host's `vkGetInstanceProcAddr` does not give.
fn missing_entry(host: &HostVulkan) -> Option<&'static CStr> {
    INSTANCE_ENTRIES.iter().copied().find(|name| {
        // SAFETY: the host's vkGetInstanceProcAddr with its live instance and a static name.
        unsafe { (host.get_instance_proc_addr)(host.instance, name.as_ptr()) }.is_none()
    })
}

/// Instance extensions the host must enable (wgpu-hal reads device features through it).
pub const INSTANCE_EXTENSIONS: [&CStr; 1] = [ash::khr::get_physical_device_properties2::NAME];

/// The host's queue lock: both calls get `user`. Needed when the host touches the queue from
/// other threads while wethair submits (on lavapipe the host and wethair share its one queue).
#[derive(Clone, Copy, Debug)]
pub struct QueueLock {
    /// Takes the lock.
    pub lock: unsafe extern "C" fn(*mut c_void),
    /// Releases it.
    pub unlock: unsafe extern "C" fn(*mut c_void),
    /// The host's pointer, passed back untouched.
    pub user: *mut c_void,
}

// SAFETY: the host promises (C API docs) that its callbacks may be called from any thread.
unsafe impl Send for QueueLock {}
// SAFETY: as above; we only pass `user` back.
unsafe impl Sync for QueueLock {}

impl QueueLock {
    /// Locks now; unlocks when the guard drops.
    pub fn guard(self: &Arc<Self>) -> QueueGuard {
        // SAFETY: the host's callback, with the host's pointer.
        unsafe { (self.lock)(self.user) };
        QueueGuard(self.clone())
    }
}

/// Holds the host's queue lock until dropped.
#[derive(Debug)]
pub struct QueueGuard(Arc<QueueLock>);

impl Drop for QueueGuard {
    fn drop(&mut self) {
        // SAFETY: paired with the lock taken in `QueueLock::guard`.
        unsafe { (self.0.unlock)(self.0.user) };
    }
}

/// The host's Vulkan objects. `device` may be null while asking for [`requirements`].
#[derive(Debug)]
pub struct HostVulkan {
    /// The loader's `vkGetInstanceProcAddr`.
    pub get_instance_proc_addr: vk::PFN_vkGetInstanceProcAddr,
    /// The host's instance.
    pub instance: vk::Instance,
    /// The physical device the host's device was (or will be) made on.
    pub physical_device: vk::PhysicalDevice,
    /// The host's device (null for [`requirements`]).
    pub device: vk::Device,
    /// Queue family of the queue wethair submits to.
    pub queue_family: u32,
    /// Index of that queue in its family.
    pub queue_index: u32,
    /// `VkApplicationInfo::apiVersion` of the instance.
    pub api_version: u32,
    /// Instance extensions the host enabled.
    pub instance_extensions: Vec<CString>,
    /// Device extensions the host enabled.
    pub device_extensions: Vec<CString>,
    /// The `VkPhysicalDeviceFeatures2` chain, or the `VkDeviceCreateInfo`, the device was
    /// created with; null leaves the feature check to the host (or to
    /// `enabled_feature_names`).
    pub enabled_features: *const c_void,
    /// The features enabled, by member name (`timeline_semaphore`), when recorded at device
    /// creation (see `gpu::intercept`); used when `enabled_features` is null.
    pub enabled_feature_names: Option<Vec<String>>,
    /// The host's queue lock, if it has one.
    pub queue_lock: Option<QueueLock>,
}

/// What the host must enable on its device, with the feature chain it can pass as
/// `VkDeviceCreateInfo::pNext`.
pub struct Requirements {
    /// Device extensions to enable (static names).
    pub device_extensions: Vec<&'static CStr>,
    /// Vulkan feature names (camelCase) the chain sets.
    pub feature_names: Vec<CString>,
    chain: Box<FeatureChain>,
}

impl std::fmt::Debug for Requirements {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Requirements")
            .field("device_extensions", &self.device_extensions)
            .field("feature_names", &self.feature_names)
            .finish()
    }
}

// SAFETY: the chain's pointers point into its own box and are only read.
unsafe impl Send for Requirements {}

/// wgpu-hal's feature structs, linked behind a `VkPhysicalDeviceFeatures2` head. Boxed, so the
/// pointers between them stay valid while the host holds the requirements.
struct FeatureChain {
    feats: hv::PhysicalDeviceFeatures,
    head: vk::PhysicalDeviceFeatures2<'static>,
}

impl Requirements {
    /// A `VkPhysicalDeviceFeatures2*` whose chain enables everything wethair needs; valid while
    /// `self` lives.
    pub fn features_chain(&self) -> *const c_void {
        &self.chain.head as *const vk::PhysicalDeviceFeatures2 as *const c_void
    }

    /// The core features wethair needs.
    #[cfg(feature = "unity")]
    pub(crate) fn core(&self) -> vk::PhysicalDeviceFeatures {
        self.chain.head.features
    }

    /// The extension structs of the chain (after the `VkPhysicalDeviceFeatures2` head), in
    /// order; they live in `self`, which a caller may relink while it holds `&mut self`.
    #[cfg(feature = "unity")]
    pub(crate) fn chained(&mut self) -> Vec<*mut vk::BaseOutStructure<'static>> {
        let mut out = Vec::new();
        let mut p = self.chain.head.p_next as *mut vk::BaseOutStructure<'static>;
        while !p.is_null() {
            out.push(p);
            // SAFETY: the chain was built from valid structs in our box.
            p = unsafe { (*p).p_next };
        }
        out
    }
}

/// The wgpu-hal instance and exposed adapter on the host's handles.
struct HalAdapter {
    instance: hv::Instance,
    exposed: wgpu::hal::ExposedAdapter<Vulkan>,
    features: wgpu::Features,
    limits: wgpu::Limits,
    extensions: Vec<&'static CStr>,
}

fn no_op_drop() -> Option<wgpu::hal::DropCallback> {
    Some(Box::new(|| ()))
}

fn names(list: &[&CStr]) -> String {
    list.iter().map(|c| c.to_string_lossy()).collect::<Vec<_>>().join(", ")
}

/// Opens wgpu-hal on the host's instance and physical device (nothing created on the GPU).
fn hal_adapter(host: &HostVulkan) -> Result<HalAdapter> {
    if host.instance == vk::Instance::null() || host.physical_device == vk::PhysicalDevice::null() {
        return Err(Error::InvalidArgument(
            "instance and physical_device must be set".into(),
        ));
    }
    if host.api_version < MIN_API_VERSION {
        return Err(Error::Unsupported(format!(
            "the host's instance uses Vulkan {}.{}; wethair needs 1.1 or later",
            vk::api_version_major(host.api_version),
            vk::api_version_minor(host.api_version)
        )));
    }
    let missing: Vec<&CStr> = INSTANCE_EXTENSIONS
        .iter()
        .copied()
        .filter(|e| !host.instance_extensions.iter().any(|h| h.as_c_str() == *e))
        .collect();
    if !missing.is_empty() {
        return Err(Error::Unsupported(format!(
            "the host's VkInstance lacks instance extensions: {}",
            names(&missing)
        )));
    }
    // A NULL entry would make wgpu-hal's loader call a stub that aborts the process.
    if let Some(name) = missing_entry(host) {
        return Err(Error::Unsupported(format!(
            "the host's vkGetInstanceProcAddr returns NULL for {} on its instance; wethair needs it",
            name.to_string_lossy()
        )));
    }
    // SAFETY: the host passes the loader's vkGetInstanceProcAddr and its live instance.
    let entry = unsafe {
        ash::Entry::from_static_fn(ash::StaticFn {
            get_instance_proc_addr: host.get_instance_proc_addr,
        })
    };
    // SAFETY: as above.
    let raw = unsafe { ash::Instance::load(entry.static_fn(), host.instance) };
    let flags = wgpu::InstanceFlags::empty();
    // Tell wgpu only what the host enabled, with the static names wgpu-hal wants.
    let mut extensions = hv::Instance::desired_extensions(&entry, host.api_version, flags)
        .map_err(|e| Error::Device(format!("listing instance extensions: {e}")))?;
    extensions.retain(|e| host.instance_extensions.iter().any(|h| h.as_c_str() == *e));
    // SAFETY: the instance was made from this entry with these extensions; the drop callback
    // leaves it to the host.
    let instance = unsafe {
        hv::Instance::from_raw(
            entry,
            raw,
            host.api_version,
            0,
            None,
            extensions,
            flags,
            wgpu::MemoryBudgetThresholds::default(),
            false,
            no_op_drop(),
        )
    }
    .map_err(|e| Error::Device(format!("wrapping the host's VkInstance: {e}")))?;
    let exposed = instance.expose_adapter(host.physical_device).ok_or_else(|| {
        Error::Unsupported(
            "wgpu cannot use the host's physical device (it needs Vulkan 1.1 and a first queue \
             family with graphics)"
                .into(),
        )
    })?;
    // wgpu uses the device's Vulkan version (its 1.2/1.3 entry points, its SPIR-V version), which
    // Vulkan only allows up to the instance's apiVersion.
    let dv = exposed.adapter.physical_device_capabilities().properties().api_version;
    let (dmaj, dmin) = (vk::api_version_major(dv), vk::api_version_minor(dv).min(3));
    let (imaj, imin) = (
        vk::api_version_major(host.api_version),
        vk::api_version_minor(host.api_version),
    );
    if (imaj, imin) < (dmaj, dmin) {
        return Err(Error::Unsupported(format!(
            "the host's instance uses Vulkan {imaj}.{imin} but its device offers {dmaj}.{dmin}, which wgpu uses: \
             create the instance with apiVersion {dmaj}.{dmin} or later"
        )));
    }
    let (features, limits) = wanted(exposed.features, &exposed.capabilities.limits);
    let mut extensions = exposed.adapter.required_device_extensions(features);
    // No surface: wethair never presents, so neither swapchain nor its dependants.
    extensions.retain(|e| !e.to_bytes().windows(9).any(|w| w == b"swapchain"));
    Ok(HalAdapter {
        instance,
        exposed,
        features,
        limits,
        extensions,
    })
}

/// What the host must enable on a device made on `host.physical_device`.
pub fn requirements(host: &HostVulkan) -> Result<Requirements> {
    requirements_of(&hal_adapter(host)?)
}

/// The requirements of an adapter already exposed.
fn requirements_of(hal: &HalAdapter) -> Result<Requirements> {
    let feats = hal
        .exposed
        .adapter
        .physical_device_features(&hal.extensions, hal.features);
    let mut chain = Box::new(FeatureChain {
        feats,
        head: vk::PhysicalDeviceFeatures2::default(),
    });
    let (core, next) = {
        let info = chain.feats.add_to_device_create(vk::DeviceCreateInfo::default());
        (info.p_enabled_features, info.p_next)
    };
    // SAFETY: `core` points at the core features inside the box, just set.
    chain.head.features = unsafe { *core };
    chain.head.p_next = next as *mut c_void;
    // SAFETY: the chain was just built from valid structs.
    let set = unsafe { enabled_names(chain.features_head()) };
    Ok(Requirements {
        device_extensions: hal.extensions.clone(),
        feature_names: set.into_iter().filter_map(|n| CString::new(camel(&n)).ok()).collect(),
        chain,
    })
}

impl FeatureChain {
    fn features_head(&self) -> *const c_void {
        &self.head as *const vk::PhysicalDeviceFeatures2 as *const c_void
    }
}

/// `robust_buffer_access` → `robustBufferAccess`, as the Vulkan spec names features.
pub(crate) fn camel(snake: &str) -> String {
    let mut out = String::new();
    let mut up = false;
    for c in snake.chars() {
        if c == '_' {
            up = true;
        } else if up {
            out.extend(c.to_uppercase());
            up = false;
        } else {
            out.push(c);
        }
    }
    out
}

/// The `VkBool32` members set in a feature struct, read from ash's `Debug`, which names them.
fn set_members(debug: &str) -> Vec<String> {
    let body = debug.split_once('{').map_or("", |b| b.1).trim_end_matches('}');
    body.split(", ")
        .filter_map(|kv| kv.split_once(": "))
        .filter(|(k, v)| !k.starts_with('_') && *k != "s_type" && *k != "p_next" && v.trim() == "1")
        .map(|(k, _)| k.trim().to_string())
        .collect()
}

/// Names the features set in one chained struct, for the struct types wgpu-hal chains and the
/// Vulkan 1.1–1.3 aggregates hosts use instead. Unknown types name nothing.
macro_rules! chained_names {
    ($p:expr, $($t:ident),* $(,)?) => {{
        let base = &*($p as *const vk::BaseInStructure);
        $(
            if base.s_type == <vk::$t as vk::TaggedStructure>::STRUCTURE_TYPE {
                return set_members(&format!("{:?}", &*($p as *const vk::$t)));
            }
        )*
        Vec::new()
    }};
}

/// # Safety
/// `p` points to a valid Vulkan struct with an `sType`.
unsafe fn struct_names(p: *const c_void) -> Vec<String> {
    chained_names!(
        p,
        PhysicalDeviceVulkan11Features,
        PhysicalDeviceVulkan12Features,
        PhysicalDeviceVulkan13Features,
        PhysicalDeviceDescriptorIndexingFeatures,
        PhysicalDeviceTimelineSemaphoreFeatures,
        PhysicalDeviceImageRobustnessFeatures,
        PhysicalDeviceRobustness2FeaturesEXT,
        PhysicalDeviceMultiviewFeatures,
        PhysicalDeviceSamplerYcbcrConversionFeatures,
        PhysicalDeviceTextureCompressionASTCHDRFeatures,
        PhysicalDeviceShaderFloat16Int8Features,
        PhysicalDevice16BitStorageFeatures,
        PhysicalDeviceZeroInitializeWorkgroupMemoryFeatures,
        PhysicalDeviceBufferDeviceAddressFeatures,
        PhysicalDeviceShaderAtomicInt64Features,
        PhysicalDeviceShaderAtomicFloatFeaturesEXT,
        PhysicalDeviceSubgroupSizeControlFeatures,
        PhysicalDeviceMaintenance4Features,
        PhysicalDeviceShaderIntegerDotProductFeatures,
        PhysicalDeviceVulkanMemoryModelFeatures,
        PhysicalDeviceShaderDrawParametersFeatures,
    )
}

/// Every feature set in a `VkPhysicalDeviceFeatures2` chain, or in a `VkDeviceCreateInfo`'s
/// `pEnabledFeatures` and `pNext` chain.
///
/// # Safety
/// `p` points to one of those, with a valid chain.
pub(crate) unsafe fn enabled_names(p: *const c_void) -> Vec<String> {
    let mut out = Vec::new();
    let mut next = p as *const vk::BaseInStructure;
    let first = &*next;
    if first.s_type == vk::StructureType::DEVICE_CREATE_INFO {
        let info = &*(p as *const vk::DeviceCreateInfo);
        if let Some(core) = info.p_enabled_features.as_ref() {
            out.extend(set_members(&format!("{core:?}")));
        }
        next = info.p_next as *const vk::BaseInStructure;
    }
    while let Some(s) = next.as_ref() {
        if s.s_type == vk::StructureType::PHYSICAL_DEVICE_FEATURES_2 {
            let f2 = &*(next as *const vk::PhysicalDeviceFeatures2);
            out.extend(set_members(&format!("{:?}", f2.features)));
        } else {
            out.extend(struct_names(next as *const c_void));
        }
        next = s.p_next;
    }
    out.sort();
    out.dedup();
    out
}

/// Opens wgpu on the host's device after checking it has what wethair needs.
pub fn open(host: &HostVulkan) -> Result<GpuDevice> {
    if host.device == vk::Device::null() {
        return Err(Error::InvalidArgument("device must be set".into()));
    }
    let hal = hal_adapter(host)?;
    let missing: Vec<&CStr> = hal
        .extensions
        .iter()
        .copied()
        .filter(|e| !host.device_extensions.iter().any(|h| h.as_c_str() == *e))
        .collect();
    if !missing.is_empty() {
        return Err(Error::Unsupported(format!(
            "the host's VkDevice lacks device extensions: {} (wethair_vulkan_requirements_create lists them)",
            names(&missing)
        )));
    }
    let have = if !host.enabled_features.is_null() {
        // SAFETY: the host passes the chain (or create info) its device was made with.
        Some(unsafe { enabled_names(host.enabled_features) })
    } else {
        host.enabled_feature_names.clone()
    };
    if let Some(have) = have {
        let need = requirements_of(&hal)?;
        let lacking: Vec<String> = need
            .feature_names
            .iter()
            .map(|c| c.to_string_lossy().into_owned())
            .filter(|n| !have.iter().any(|h| camel(h) == *n))
            .collect();
        if !lacking.is_empty() {
            return Err(Error::Unsupported(format!(
                "the host's VkDevice lacks Vulkan features: {} (chain the requirements' features into VkDeviceCreateInfo)",
                lacking.join(", ")
            )));
        }
    }
    let raw_instance = hal.instance.shared_instance().raw_instance().clone();
    // SAFETY: the host's device was made from this instance.
    let device = unsafe { ash::Device::load(raw_instance.fp_v1_0(), host.device) };
    let sync = SharedSync::new(device.clone(), host.queue_lock.map(Arc::new))?;
    let hints = wgpu::MemoryHints::Performance;
    // SAFETY: the device was made on this adapter with these extensions and features (checked
    // above where the host let us); the drop callback leaves it to the host.
    let open = unsafe {
        hal.exposed.adapter.device_from_raw(
            device,
            no_op_drop(),
            &hal.extensions,
            hal.features,
            &hal.limits,
            &hints,
            host.queue_family,
            host.queue_index,
        )
    }
    .map_err(|e| Error::Device(format!("wrapping the host's VkDevice: {e}")))?;
    let info = hal.exposed.info.clone();
    // SAFETY: the hal instance is a valid Vulkan instance; it owns nothing of the host's.
    let instance = unsafe { wgpu::Instance::from_hal::<Vulkan>(hal.instance) };
    // SAFETY: the adapter was exposed by this instance.
    let adapter = unsafe { instance.create_adapter_from_hal(hal.exposed) };
    // SAFETY: the device was opened on this adapter with these features.
    let (device, queue) = unsafe { adapter.create_device_from_hal(open, &descriptor(hal.features, &hal.limits)) }
        .map_err(|e| Error::Device(format!("opening wgpu on the host's device: {e}")))?;
    let mut dev = GpuDevice::from_parts(info, device, queue, hal.limits, hal.features);
    dev.shared = Some(sync);
    Ok(dev)
}
