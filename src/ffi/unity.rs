//! Unity native plugin support: the plugin entry points (`UnityPluginLoad`/`UnityPluginUnload`,
//! cargo feature `unity`), the device-event callback, simulations on Unity's own VkDevice,
//! and a render-thread event that steps a simulation.
//!
//! The interface structs are declared here from Unity's public plugin headers
//! (IUnityInterface.h, IUnityGraphics.h, IUnityGraphicsVulkan.h); calls use `extern "system"`
//! (Unity's `UNITY_INTERFACE_API`, stdcall on 32-bit Windows). On Vulkan, the plugin intercepts
//! Unity's instance and device creation to add what wethair needs (the plugin must load at
//! startup: "Load on startup" in its import settings); on any other renderer, or when that did
//! not happen, simulations run on their own device or the CPU.

use super::boundary::WetHairResult;
use super::sim::WetHairSim;
use super::types::WetHairSimDesc;
use std::ffi::c_void;

/// What the Unity plugin knows (`wethair_unity_get_status`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairUnityStatus {
    /// `sizeof(WetHairUnityStatus)`, set by the host before the call.
    pub struct_size: u32,
    /// 1 between `UnityPluginLoad` and `UnityPluginUnload`.
    pub loaded: u32,
    /// Unity's `UnityGfxRenderer` (21 = Vulkan, 2 = D3D11, 18 = D3D12, 16 = Metal, 17 = OpenGL
    /// core, 4 = null), or -1 before the graphics device is known.
    pub renderer: i32,
    /// 1 when simulations are created on Unity's own VkDevice.
    pub on_unity_device: u32,
    /// First of the render event ids reserved for wethair (`wethair_unity_get_render_event_func`).
    pub event_id_base: i32,
    /// Reserved, 0.
    pub reserved: u32,
    /// Why simulations are not on Unity's device (empty when they are), NUL-terminated.
    pub reason: [u8; 256],
}

impl WetHairUnityStatus {
    /// Nothing known yet: not loaded, no renderer.
    fn unknown() -> Self {
        WetHairUnityStatus {
            struct_size: std::mem::size_of::<WetHairUnityStatus>() as u32,
            loaded: 0,
            renderer: -1,
            on_unity_device: 0,
            event_id_base: 0,
            reserved: 0,
            reason: [0; 256],
        }
    }
}

/// One render-thread step (`GL.IssuePluginEventAndData` / `CommandBuffer.IssuePluginEventAndData`
/// with the event id `event_id_base` and a pointer to this, pinned by the caller).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairUnityStep {
    /// `sizeof(WetHairUnityStep)`.
    pub struct_size: u32,
    /// Seconds to advance.
    pub dt: f32,
    /// The simulation.
    pub sim: *mut WetHairSim,
    /// Written by the event: the step's `WetHairResult` (the render thread has no caller to
    /// return it to); read it on the main thread a frame later.
    pub result: u32,
    /// Reserved, 0.
    pub reserved: u32,
}

/// The render event function type (`UnityRenderingEventAndData`).
pub type WetHairUnityRenderEvent = Option<unsafe extern "system" fn(event_id: i32, data: *mut c_void)>;

#[cfg(feature = "unity")]
mod plugin {
    use ash::vk;
    use std::ffi::c_void;
    use std::sync::Mutex;

    /// `UnityInterfaceGUID`.
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct UnityInterfaceGuid {
        /// High 64 bits.
        pub high: u64,
        /// Low 64 bits.
        pub low: u64,
    }

    /// `IUnityInterfaces`: Unity's registry of interfaces.
    #[repr(C)]
    #[derive(Debug)]
    pub struct IUnityInterfaces {
        /// `GetInterface(guid)`.
        pub get_interface: Option<unsafe extern "system" fn(UnityInterfaceGuid) -> *mut c_void>,
        /// `RegisterInterface(guid, ptr)`.
        pub register_interface: Option<unsafe extern "system" fn(UnityInterfaceGuid, *mut c_void)>,
        /// `GetInterfaceSplit(high, low)`.
        pub get_interface_split: Option<unsafe extern "system" fn(u64, u64) -> *mut c_void>,
        /// `RegisterInterfaceSplit(high, low, ptr)`.
        pub register_interface_split: Option<unsafe extern "system" fn(u64, u64, *mut c_void)>,
    }

    /// `IUnityGraphicsDeviceEventCallback`.
    pub type DeviceEventCallback = unsafe extern "system" fn(event: i32);

    /// `IUnityGraphics`.
    #[repr(C)]
    #[derive(Debug)]
    pub struct IUnityGraphics {
        /// `GetRenderer()`: a `UnityGfxRenderer`.
        pub get_renderer: Option<unsafe extern "system" fn() -> i32>,
        /// `RegisterDeviceEventCallback(cb)`.
        pub register_device_event_callback: Option<unsafe extern "system" fn(Option<DeviceEventCallback>)>,
        /// `UnregisterDeviceEventCallback(cb)`.
        pub unregister_device_event_callback: Option<unsafe extern "system" fn(Option<DeviceEventCallback>)>,
        /// `ReserveEventIDRange(count)`: the first id.
        pub reserve_event_id_range: Option<unsafe extern "system" fn(i32) -> i32>,
    }

    /// `UnityVulkanInstance`: Unity's Vulkan objects.
    #[repr(C)]
    #[derive(Clone, Copy, Debug)]
    pub struct UnityVulkanInstance {
        /// `VkPipelineCache`.
        pub pipeline_cache: u64,
        /// `VkInstance`.
        pub instance: *mut c_void,
        /// `VkPhysicalDevice`.
        pub physical_device: *mut c_void,
        /// `VkDevice`.
        pub device: *mut c_void,
        /// `VkQueue` (graphics).
        pub graphics_queue: *mut c_void,
        /// The loader's `vkGetInstanceProcAddr`.
        pub get_instance_proc_addr: *const c_void,
        /// The graphics queue's family.
        pub queue_family_index: u32,
        /// Reserved.
        pub reserved: [*mut c_void; 8],
    }

    /// `UnityVulkanPluginEventConfig`.
    #[repr(C)]
    #[derive(Clone, Copy, Debug)]
    pub struct UnityVulkanPluginEventConfig {
        /// `UnityVulkanEventRenderPassPreCondition` (2 = ensure outside).
        pub render_pass_precondition: i32,
        /// `UnityVulkanGraphicsQueueAccess` (1 = allow).
        pub graphics_queue_access: i32,
        /// `UnityVulkanEventConfigFlagBits`.
        pub flags: u32,
    }

    /// `UnityVulkanInitCallback`.
    pub type InitCallback =
        unsafe extern "system" fn(vk::PFN_vkGetInstanceProcAddr, *mut c_void) -> vk::PFN_vkGetInstanceProcAddr;

    /// `IUnityGraphicsVulkan` (the first members; the rest are not called).
    #[repr(C)]
    #[derive(Debug)]
    pub struct IUnityGraphicsVulkan {
        /// `InterceptInitialization(func, userdata)`.
        pub intercept_initialization: Option<unsafe extern "system" fn(Option<InitCallback>, *mut c_void) -> bool>,
        /// `InterceptVulkanAPI(name, func)`.
        pub intercept_vulkan_api: *const c_void,
        /// `ConfigureEvent(eventId, config)`.
        pub configure_event: Option<unsafe extern "system" fn(i32, *const UnityVulkanPluginEventConfig)>,
        /// `Instance()`.
        pub instance: Option<unsafe extern "system" fn() -> UnityVulkanInstance>,
    }

    /// IUnityGraphics's GUID (IUnityGraphics.h).
    pub const GRAPHICS_GUID: UnityInterfaceGuid = UnityInterfaceGuid {
        high: 0x7CBA_0A9C_A4DD_B544,
        low: 0x8C5A_D492_6EB1_7B11,
    };
    /// IUnityGraphicsVulkan's GUID (IUnityGraphicsVulkan.h).
    pub const VULKAN_GUID: UnityInterfaceGuid = UnityInterfaceGuid {
        high: 0x9535_5348_d4ef_4e11,
        low: 0x9789_313d_fcff_cc87,
    };
    /// `kUnityGfxRendererVulkan`.
    pub const RENDERER_VULKAN: i32 = 21;
    /// Render event ids wethair reserves.
    pub const EVENT_COUNT: i32 = 1;

    /// The plugin's state between load and unload (pointers as integers: Unity's objects outlive it).
    #[derive(Debug, Default)]
    pub struct Plugin {
        pub graphics: usize,
        pub vulkan: usize,
        pub renderer: i32,
        pub event_base: i32,
        pub intercepted: bool,
        pub unity_vulkan: Option<(usize, usize, usize, usize, usize, u32)>,
    }

    pub static PLUGIN: Mutex<Option<Plugin>> = Mutex::new(None);

    pub fn with<R>(f: impl FnOnce(&mut Option<Plugin>) -> R) -> R {
        f(&mut PLUGIN.lock().unwrap_or_else(|e| e.into_inner()))
    }

    /// Looks an interface up by GUID (the split form first: no struct passed by value).
    pub unsafe fn get(interfaces: *mut IUnityInterfaces, guid: UnityInterfaceGuid) -> *mut c_void {
        let Some(i) = interfaces.as_ref() else {
            return std::ptr::null_mut();
        };
        if let Some(f) = i.get_interface_split {
            return f(guid.high, guid.low);
        }
        i.get_interface.map_or(std::ptr::null_mut(), |f| f(guid))
    }

    pub unsafe extern "system" fn on_init(
        gipa: vk::PFN_vkGetInstanceProcAddr,
        _user: *mut c_void,
    ) -> vk::PFN_vkGetInstanceProcAddr {
        with(|p| {
            if let Some(p) = p {
                p.intercepted = true;
            }
        });
        crate::gpu::intercept::install(gipa)
    }

    /// Unity's device events: 0 initialize, 1 shutdown.
    pub unsafe extern "system" fn on_device_event(event: i32) {
        let _ = std::panic::catch_unwind(|| device_event(event));
    }

    fn device_event(event: i32) {
        with(|p| {
            let Some(p) = p else { return };
            match event {
                0 => {
                    // SAFETY: Unity's interface, valid while the plugin is loaded.
                    let g = unsafe { (p.graphics as *const IUnityGraphics).as_ref() };
                    p.renderer = g.and_then(|g| g.get_renderer).map_or(-1, |f| unsafe { f() });
                    p.unity_vulkan = None;
                    if p.renderer == RENDERER_VULKAN {
                        // SAFETY: as above.
                        let v = unsafe { (p.vulkan as *const IUnityGraphicsVulkan).as_ref() };
                        if let Some(inst) = v.and_then(|v| v.instance).map(|f| unsafe { f() }) {
                            p.unity_vulkan = Some((
                                inst.instance as usize,
                                inst.physical_device as usize,
                                inst.device as usize,
                                inst.graphics_queue as usize,
                                inst.get_instance_proc_addr as usize,
                                inst.queue_family_index,
                            ));
                        }
                        if let Some(f) = v.and_then(|v| v.configure_event) {
                            // Outside a render pass, with the graphics queue ours to submit to.
                            let cfg = UnityVulkanPluginEventConfig {
                                render_pass_precondition: 2,
                                graphics_queue_access: 1,
                                flags: 1 | 2,
                            };
                            // SAFETY: Unity's function, a valid config.
                            unsafe { f(p.event_base, &cfg) };
                        }
                    }
                }
                1 => {
                    p.renderer = -1;
                    p.unity_vulkan = None;
                }
                _ => {}
            }
        })
    }
}

#[cfg(feature = "unity")]
pub use plugin::{IUnityGraphics, IUnityGraphicsVulkan, IUnityInterfaces, UnityInterfaceGuid, UnityVulkanInstance};

/// Unity calls this when it loads the plugin. Registers for graphics device events; on
/// Vulkan, asks to intercept Unity's instance and device creation (effective only when the
/// plugin loads at startup).
///
/// # Safety
/// `interfaces` is Unity's registry (or NULL, which loads a plugin that only runs simulations on
/// their own devices).
#[cfg(feature = "unity")]
#[no_mangle]
pub unsafe extern "system" fn UnityPluginLoad(interfaces: *mut IUnityInterfaces) {
    use plugin::*;
    let _ = std::panic::catch_unwind(|| {
        let graphics = get(interfaces, GRAPHICS_GUID) as *mut IUnityGraphics;
        let vulkan = get(interfaces, VULKAN_GUID) as *mut IUnityGraphicsVulkan;
        let g = graphics.as_ref();
        let event_base = g
            .and_then(|g| g.reserve_event_id_range)
            .map_or(0x5745_0000, |f| f(EVENT_COUNT));
        with(|p| {
            *p = Some(Plugin {
                graphics: graphics as usize,
                vulkan: vulkan as usize,
                renderer: -1,
                event_base,
                intercepted: false,
                unity_vulkan: None,
            })
        });
        if let Some(f) = vulkan.as_ref().and_then(|v| v.intercept_initialization) {
            f(Some(on_init), std::ptr::null_mut());
        }
        if let Some(f) = g.and_then(|g| g.register_device_event_callback) {
            f(Some(on_device_event));
            // The device may exist already (plugin loaded late): run the initialize event now.
            on_device_event(0);
        }
    });
}

/// Unity calls this when it unloads the plugin: unregisters the callback and forgets Unity's
/// objects. Simulations the scripts still hold keep working on their own devices' terms.
///
/// # Safety
/// Called by Unity after `UnityPluginLoad`.
#[cfg(feature = "unity")]
#[no_mangle]
pub unsafe extern "system" fn UnityPluginUnload() {
    use plugin::*;
    let _ = std::panic::catch_unwind(|| {
        let graphics = with(|p| p.take().map_or(0, |p| p.graphics)) as *const IUnityGraphics;
        if let Some(f) = graphics.as_ref().and_then(|g| g.unregister_device_event_callback) {
            f(Some(on_device_event));
        }
        crate::gpu::intercept::clear();
    });
}

/// Describes the plugin's state. The host sets `out->struct_size` first.
///
/// # Safety
/// `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_unity_get_status(out: *mut WetHairUnityStatus) -> WetHairResult {
    boundary!({
        let out = check_out_size!(out, WetHairUnityStatus, "out");
        let mut st = WetHairUnityStatus::unknown();
        let reason = unity_device(&mut st).err().unwrap_or_default();
        let n = reason.len().min(255);
        st.reason[..n].copy_from_slice(&reason.as_bytes()[..n]);
        out.write(st);
        Ok(())
    })
}

/// Fills the loaded/renderer/event fields; Ok with Unity's device description when simulations
/// go on it, else why not.
#[cfg(feature = "unity")]
fn unity_device(st: &mut WetHairUnityStatus) -> Result<crate::gpu::vulkan::HostVulkan, String> {
    use plugin::*;
    let (renderer, base, intercepted, uv) = with(|p| match p {
        Some(p) => {
            st.loaded = 1;
            (p.renderer, p.event_base, p.intercepted, p.unity_vulkan)
        }
        None => (-1, 0, false, None),
    });
    st.renderer = renderer;
    st.event_id_base = base;
    if st.loaded == 0 {
        return Err("the Unity plugin is not loaded (UnityPluginLoad was not called)".into());
    }
    if renderer != RENDERER_VULKAN {
        return Err(format!(
            "Unity's renderer is {renderer}, not Vulkan (21): simulations use their own device"
        ));
    }
    let Some((_, _, device, queue, _, family)) = uv else {
        return Err("Unity's Vulkan instance data is not available".into());
    };
    if !intercepted {
        return Err("Unity's Vulkan initialization was not intercepted: set the plugin to load on startup".into());
    }
    let rec = crate::gpu::intercept::recorded().ok_or("nothing was recorded at Unity's device creation")?;
    if ash::vk::Handle::as_raw(rec.device) as usize != device {
        return Err("Unity's device is not the one created through the interception".into());
    }
    if !rec.missing.is_empty() {
        return Err(format!("Unity's device lacks: {}", rec.missing.join(", ")));
    }
    // The queue's index in its family: the one whose handle is Unity's graphics queue.
    let index = queue_index(&rec, family, queue).ok_or("Unity's graphics queue was not found on its device")?;
    let host = crate::gpu::intercept::host(&rec, family, index).ok_or("no vkGetInstanceProcAddr recorded")?;
    st.on_unity_device = 1;
    Ok(host)
}

/// Index of `queue` in `family` on the recorded device.
#[cfg(feature = "unity")]
fn queue_index(rec: &crate::gpu::intercept::Recorded, family: u32, queue: usize) -> Option<u32> {
    use ash::vk::{self, Handle};
    let gipa = rec.real_gipa?;
    // SAFETY: the recorded instance and device are Unity's, alive while its device is.
    unsafe {
        let gdpa: vk::PFN_vkGetDeviceProcAddr =
            std::mem::transmute(gipa(rec.instance, c"vkGetDeviceProcAddr".as_ptr())?);
        let get_queue: vk::PFN_vkGetDeviceQueue = std::mem::transmute(gdpa(rec.device, c"vkGetDeviceQueue".as_ptr())?);
        (0..16).find(|&i| {
            let mut q = vk::Queue::null();
            get_queue(rec.device, family, i, &mut q);
            q.as_raw() as usize == queue
        })
    }
}

#[cfg(not(feature = "unity"))]
fn unity_device(_st: &mut WetHairUnityStatus) -> Result<(), String> {
    Err("this build has no Unity plugin (cargo feature `unity`)".into())
}

/// Creates a simulation for Unity: on Unity's own VkDevice when the plugin intercepted its
/// creation (see `wethair_unity_get_status`), else as `wethair_sim_create` does.
///
/// # Safety
/// As `wethair_sim_create`.
#[no_mangle]
pub unsafe extern "C" fn wethair_unity_sim_create(
    desc: *const WetHairSimDesc,
    out: *mut *mut WetHairSim,
) -> WetHairResult {
    let mut st = WetHairUnityStatus::unknown();
    #[cfg(feature = "unity")]
    if let Ok(host) = unity_device(&mut st) {
        return boundary!({
            let d = read_def!(desc, WetHairSimDesc, "desc");
            if out.is_null() {
                return Err(super::boundary::null("out"));
            }
            let groom: &super::groom::WetHairGroom = nonnull!(d.groom, "desc->groom");
            let sim = crate::sim::Simulation::new_on_vulkan(&groom.0, d.params()?, &host)?;
            out.write(Box::into_raw(Box::new(WetHairSim(sim))));
            Ok(())
        });
    }
    let _ = &mut st;
    super::sim::wethair_sim_create(desc, out)
}

/// The render event (`UnityRenderingEventAndData`): with `event_id_base` and a
/// `WetHairUnityStep*`, steps that simulation on Unity's render thread and writes the result
/// into the struct. Other event ids and NULL data are ignored.
///
/// # Safety
/// Unity calls it with the data pointer the script passed.
unsafe extern "system" fn render_event(event_id: i32, data: *mut c_void) {
    let _ = std::panic::catch_unwind(|| {
        #[cfg(feature = "unity")]
        let base = plugin::with(|p| p.as_ref().map_or(0, |p| p.event_base));
        #[cfg(not(feature = "unity"))]
        let base = 0;
        let step = data as *mut WetHairUnityStep;
        if event_id != base || step.is_null() {
            return;
        }
        if std::ptr::read_unaligned(step as *const u32) as usize != std::mem::size_of::<WetHairUnityStep>() {
            (*step).result = WetHairResult::WETHAIR_ERROR_STRUCT_SIZE as u32;
            return;
        }
        let r = super::sim::wethair_sim_step((*step).sim, (*step).dt);
        (*step).result = r as u32;
    });
}

/// The render event function to pass to `GL.IssuePluginEventAndData` /
/// `CommandBuffer.IssuePluginEventAndData`, with event id `event_id_base`.
#[no_mangle]
pub extern "C" fn wethair_unity_get_render_event_func() -> WetHairUnityRenderEvent {
    Some(render_event)
}
