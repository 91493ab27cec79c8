//! Adding wethair's Vulkan requirements to the host's own `vkCreateInstance` and
//! `vkCreateDevice`, for engines that let a plugin intercept them (Unity's
//! `IUnityGraphicsVulkan::InterceptInitialization`) instead of letting it choose extensions.
//!
//! The hook adds what is missing and records what the device ended up with, so a simulation
//! created later on that device can be checked like any host's ([`super::vulkan::open`]).
//! It never removes or rewrites what the engine asked for. Where a required feature sits in
//! a struct the engine already chains (a Vulkan 1.x aggregate, say), it is not added but
//! recorded as missing, and creating a simulation on that device is refused with its name.

use super::vulkan::{camel, enabled_names, requirements, HostVulkan, INSTANCE_EXTENSIONS};
use ash::vk;
use std::ffi::{c_char, c_void, CStr, CString};
use std::sync::Mutex;

/// What the hooks saw and did.
#[derive(Clone, Debug, Default)]
pub struct Recorded {
    /// The loader's `vkGetInstanceProcAddr` the engine passed in.
    pub real_gipa: Option<vk::PFN_vkGetInstanceProcAddr>,
    /// The instance created through the hook, its API version and extensions.
    pub instance: vk::Instance,
    /// `apiVersion` the instance was created with.
    pub api_version: u32,
    /// Instance extensions enabled.
    pub instance_extensions: Vec<CString>,
    /// The device created through the hook and its physical device.
    pub device: vk::Device,
    /// Its physical device.
    pub physical_device: vk::PhysicalDevice,
    /// Device extensions enabled.
    pub device_extensions: Vec<CString>,
    /// Feature members enabled (snake_case, as `enabled_names` reads them).
    pub feature_names: Vec<String>,
    /// What could not be added, if anything (requirement errors or feature names).
    pub missing: Vec<String>,
}

static RECORDED: Mutex<Option<Recorded>> = Mutex::new(None);

fn with<R>(f: impl FnOnce(&mut Option<Recorded>) -> R) -> R {
    let mut g = RECORDED.lock().unwrap_or_else(|e| e.into_inner());
    f(&mut g)
}

/// Starts intercepting: returns the `vkGetInstanceProcAddr` the engine should use from now on.
pub fn install(real: vk::PFN_vkGetInstanceProcAddr) -> vk::PFN_vkGetInstanceProcAddr {
    with(|r| {
        *r = Some(Recorded {
            real_gipa: Some(real),
            ..Default::default()
        })
    });
    hook_gipa
}

/// What the hooks recorded so far.
pub fn recorded() -> Option<Recorded> {
    with(|r| r.clone())
}

/// Forgets everything (plugin unload).
pub fn clear() {
    with(|r| *r = None);
}

/// The host description of the recorded device, with its queue, for [`super::vulkan::open`].
pub fn host(rec: &Recorded, queue_family: u32, queue_index: u32) -> Option<HostVulkan> {
    Some(HostVulkan {
        get_instance_proc_addr: rec.real_gipa?,
        instance: rec.instance,
        physical_device: rec.physical_device,
        device: rec.device,
        queue_family,
        queue_index,
        api_version: rec.api_version,
        instance_extensions: rec.instance_extensions.clone(),
        device_extensions: rec.device_extensions.clone(),
        enabled_features: std::ptr::null(),
        enabled_feature_names: Some(rec.feature_names.clone()),
        queue_lock: None,
    })
}

fn real_gipa() -> Option<vk::PFN_vkGetInstanceProcAddr> {
    with(|r| r.as_ref().and_then(|r| r.real_gipa))
}

unsafe extern "system" fn hook_gipa(instance: vk::Instance, name: *const c_char) -> vk::PFN_vkVoidFunction {
    let real = real_gipa()?;
    if !name.is_null() {
        let n = CStr::from_ptr(name);
        if n == c"vkCreateInstance" {
            let f: vk::PFN_vkCreateInstance = hook_create_instance;
            return Some(std::mem::transmute::<
                vk::PFN_vkCreateInstance,
                unsafe extern "system" fn(),
            >(f));
        }
        if n == c"vkCreateDevice" {
            let f: vk::PFN_vkCreateDevice = hook_create_device;
            return Some(std::mem::transmute::<vk::PFN_vkCreateDevice, unsafe extern "system" fn()>(f));
        }
    }
    real(instance, name)
}

unsafe fn names(p: *const *const c_char, n: u32) -> Vec<*const c_char> {
    if p.is_null() || n == 0 {
        return Vec::new();
    }
    std::slice::from_raw_parts(p, n as usize).to_vec()
}

unsafe fn owned(list: &[*const c_char]) -> Vec<CString> {
    list.iter().map(|&c| CStr::from_ptr(c).to_owned()).collect()
}

/// Instance extensions the loader offers.
unsafe fn available_instance_extensions(real: vk::PFN_vkGetInstanceProcAddr) -> Vec<CString> {
    let Some(f) = real(vk::Instance::null(), c"vkEnumerateInstanceExtensionProperties".as_ptr()) else {
        return Vec::new();
    };
    let f: vk::PFN_vkEnumerateInstanceExtensionProperties = std::mem::transmute(f);
    let mut n = 0u32;
    if f(std::ptr::null(), &mut n, std::ptr::null_mut()) != vk::Result::SUCCESS {
        return Vec::new();
    }
    let mut props = vec![vk::ExtensionProperties::default(); n as usize];
    if f(std::ptr::null(), &mut n, props.as_mut_ptr()) != vk::Result::SUCCESS {
        return Vec::new();
    }
    props.truncate(n as usize);
    props
        .iter()
        .filter_map(|p| p.extension_name_as_c_str().ok().map(|c| c.to_owned()))
        .collect()
}

/// The loader's instance version (1.0 when it cannot say).
unsafe fn loader_version(real: vk::PFN_vkGetInstanceProcAddr) -> u32 {
    let Some(f) = real(vk::Instance::null(), c"vkEnumerateInstanceVersion".as_ptr()) else {
        return vk::API_VERSION_1_0;
    };
    let f: vk::PFN_vkEnumerateInstanceVersion = std::mem::transmute(f);
    let mut v = vk::API_VERSION_1_0;
    if f(&mut v) == vk::Result::SUCCESS {
        v
    } else {
        vk::API_VERSION_1_0
    }
}

unsafe extern "system" fn hook_create_instance(
    info: *const vk::InstanceCreateInfo<'_>,
    alloc: *const vk::AllocationCallbacks<'_>,
    out: *mut vk::Instance,
) -> vk::Result {
    let Some(real) = real_gipa() else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    let Some(create) = real(vk::Instance::null(), c"vkCreateInstance".as_ptr()) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    let create: vk::PFN_vkCreateInstance = std::mem::transmute(create);
    let mut ci = *info;
    let mut exts = names(ci.pp_enabled_extension_names, ci.enabled_extension_count);
    let offered = available_instance_extensions(real);
    for e in INSTANCE_EXTENSIONS {
        let have = exts.iter().any(|&c| CStr::from_ptr(c) == e);
        if !have && offered.iter().any(|o| o.as_c_str() == e) {
            exts.push(e.as_ptr());
        }
    }
    ci.enabled_extension_count = exts.len() as u32;
    ci.pp_enabled_extension_names = exts.as_ptr();
    // wgpu uses the device's Vulkan version, which the instance must allow: ask for the
    // loader's newest, up to the 1.3 that wgpu knows (never less than the engine asked for).
    let mut app = ci.p_application_info.as_ref().copied().unwrap_or_default();
    let newest = loader_version(real).min(vk::API_VERSION_1_3);
    if app.api_version < newest {
        app.api_version = newest;
    }
    ci.p_application_info = &app;
    let r = create(&ci, alloc, out);
    if r == vk::Result::SUCCESS {
        let exts = owned(&exts);
        with(|rec| {
            if let Some(rec) = rec {
                rec.instance = *out;
                rec.api_version = app.api_version;
                rec.instance_extensions = exts;
            }
        });
    }
    r
}

/// The Vulkan 1.x aggregate that holds a promoted feature struct's members, if any.
fn aggregate_of(s: vk::StructureType) -> Option<vk::StructureType> {
    use vk::StructureType as T;
    match s {
        T::PHYSICAL_DEVICE_MULTIVIEW_FEATURES
        | T::PHYSICAL_DEVICE_SAMPLER_YCBCR_CONVERSION_FEATURES
        | T::PHYSICAL_DEVICE_16BIT_STORAGE_FEATURES
        | T::PHYSICAL_DEVICE_SHADER_DRAW_PARAMETERS_FEATURES => Some(T::PHYSICAL_DEVICE_VULKAN_1_1_FEATURES),
        T::PHYSICAL_DEVICE_TIMELINE_SEMAPHORE_FEATURES
        | T::PHYSICAL_DEVICE_DESCRIPTOR_INDEXING_FEATURES
        | T::PHYSICAL_DEVICE_SHADER_FLOAT16_INT8_FEATURES
        | T::PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES
        | T::PHYSICAL_DEVICE_SHADER_ATOMIC_INT64_FEATURES
        | T::PHYSICAL_DEVICE_VULKAN_MEMORY_MODEL_FEATURES => Some(T::PHYSICAL_DEVICE_VULKAN_1_2_FEATURES),
        T::PHYSICAL_DEVICE_IMAGE_ROBUSTNESS_FEATURES
        | T::PHYSICAL_DEVICE_ZERO_INITIALIZE_WORKGROUP_MEMORY_FEATURES
        | T::PHYSICAL_DEVICE_SUBGROUP_SIZE_CONTROL_FEATURES
        | T::PHYSICAL_DEVICE_MAINTENANCE_4_FEATURES
        | T::PHYSICAL_DEVICE_SHADER_INTEGER_DOT_PRODUCT_FEATURES
        | T::PHYSICAL_DEVICE_TEXTURE_COMPRESSION_ASTC_HDR_FEATURES => Some(T::PHYSICAL_DEVICE_VULKAN_1_3_FEATURES),
        _ => None,
    }
}

/// ORs the `VkBool32` members of two core feature structs.
fn or_core(a: &mut vk::PhysicalDeviceFeatures, b: &vk::PhysicalDeviceFeatures) {
    const N: usize = std::mem::size_of::<vk::PhysicalDeviceFeatures>() / 4;
    // SAFETY: VkPhysicalDeviceFeatures is N VkBool32 (u32) members and nothing else.
    let (a, b) = unsafe {
        (
            std::slice::from_raw_parts_mut(a as *mut _ as *mut u32, N),
            std::slice::from_raw_parts(b as *const _ as *const u32, N),
        )
    };
    for (x, y) in a.iter_mut().zip(b) {
        *x |= *y;
    }
}

unsafe extern "system" fn hook_create_device(
    phys: vk::PhysicalDevice,
    info: *const vk::DeviceCreateInfo<'_>,
    alloc: *const vk::AllocationCallbacks<'_>,
    out: *mut vk::Device,
) -> vk::Result {
    let Some(rec) = recorded() else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    let Some(real) = rec.real_gipa else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    let Some(create) = real(rec.instance, c"vkCreateDevice".as_ptr()) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    let create: vk::PFN_vkCreateDevice = std::mem::transmute(create);
    let host = HostVulkan {
        get_instance_proc_addr: real,
        instance: rec.instance,
        physical_device: phys,
        device: vk::Device::null(),
        queue_family: 0,
        queue_index: 0,
        api_version: rec.api_version,
        instance_extensions: rec.instance_extensions.clone(),
        device_extensions: Vec::new(),
        enabled_features: std::ptr::null(),
        enabled_feature_names: None,
        queue_lock: None,
    };
    let mut req = match requirements(&host) {
        Ok(r) => r,
        Err(e) => {
            // Not ours to refuse: the engine's device is created as it asked.
            let r = create(phys, info, alloc, out);
            with(|g| {
                if let Some(g) = g {
                    g.missing = vec![e.to_string()];
                }
            });
            return r;
        }
    };
    let mut ci = *info;
    let mut exts = names(ci.pp_enabled_extension_names, ci.enabled_extension_count);
    for e in &req.device_extensions {
        if !exts.iter().any(|&c| CStr::from_ptr(c) == *e) {
            exts.push(e.as_ptr());
        }
    }
    ci.enabled_extension_count = exts.len() as u32;
    ci.pp_enabled_extension_names = exts.as_ptr();
    // The engine's chain: which struct types it already has.
    let mut theirs = Vec::new();
    let mut p = ci.p_next as *const vk::BaseInStructure<'_>;
    while let Some(s) = p.as_ref() {
        theirs.push(s.s_type);
        p = s.p_next;
    }
    // Core features: OR ours into a copy of pEnabledFeatures, or of a VkPhysicalDeviceFeatures2
    // that heads the engine's chain; elsewhere in the chain it is left alone (and checked).
    let mut core = ci.p_enabled_features.as_ref().copied().unwrap_or_default();
    let f2_heads = theirs.first() == Some(&vk::StructureType::PHYSICAL_DEVICE_FEATURES_2);
    let mut head_f2: vk::PhysicalDeviceFeatures2<'_> = if f2_heads {
        *(ci.p_next as *const vk::PhysicalDeviceFeatures2<'_>)
    } else {
        Default::default()
    };
    let mut next = ci.p_next as *mut c_void;
    if f2_heads {
        or_core(&mut head_f2.features, &req.core());
        next = &mut head_f2 as *mut _ as *mut c_void;
    } else if !theirs.contains(&vk::StructureType::PHYSICAL_DEVICE_FEATURES_2) {
        or_core(&mut core, &req.core());
        ci.p_enabled_features = &core;
    }
    // Our extension structs, ahead of the engine's, where it has neither the struct nor the
    // Vulkan 1.x aggregate that holds its members.
    for s in req.chained().into_iter().rev() {
        let t = (*s).s_type;
        if theirs.contains(&t) || aggregate_of(t).is_some_and(|a| theirs.contains(&a)) {
            continue;
        }
        (*s).p_next = next as *mut vk::BaseOutStructure<'static>;
        next = s as *mut c_void;
    }
    ci.p_next = next;
    let r = create(phys, &ci, alloc, out);
    if r == vk::Result::SUCCESS {
        let have = enabled_names(&ci as *const vk::DeviceCreateInfo<'_> as *const c_void);
        let missing: Vec<String> = req
            .feature_names
            .iter()
            .map(|c| c.to_string_lossy().into_owned())
            .filter(|n| !have.iter().any(|h| camel(h) == *n))
            .collect();
        let exts = owned(&exts);
        with(|g| {
            if let Some(g) = g {
                g.device = *out;
                g.physical_device = phys;
                g.device_extensions = exts;
                g.feature_names = have;
                g.missing = missing;
            }
        });
    }
    r
}
