//! The Unity plugin entry points against hand-built interface tables (no Unity here): loaded
//! with no interfaces, with no graphics device, and with a fake device reporting a non-Vulkan
//! renderer; each falls back cleanly (simulations on their own device or the CPU, the render
//! event steps them), and unloading unregisters the callback and leaves no allocation behind.
#![cfg(feature = "unity")]

use std::alloc::{GlobalAlloc, Layout, System};
use std::ffi::c_void;
use std::sync::atomic::{AtomicI64, AtomicPtr, AtomicUsize, Ordering};
use wethair::ffi::*;

/// Counts live heap bytes, to check that load + unload leaves nothing allocated.
struct Counting;
static LIVE: AtomicI64 = AtomicI64::new(0);
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        LIVE.fetch_add(l.size() as i64, Ordering::SeqCst);
        System.alloc(l)
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size() as i64, Ordering::SeqCst);
        System.dealloc(p, l)
    }
}
#[global_allocator]
static A: Counting = Counting;

static RENDERER: AtomicI64 = AtomicI64::new(2);
static REGISTERED: AtomicUsize = AtomicUsize::new(0);
static UNREGISTERED: AtomicUsize = AtomicUsize::new(0);
static CALLBACK: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());
static GRAPHICS: AtomicPtr<c_void> = AtomicPtr::new(std::ptr::null_mut());

unsafe extern "system" fn get_renderer() -> i32 {
    RENDERER.load(Ordering::SeqCst) as i32
}
unsafe extern "system" fn register(cb: Option<unsafe extern "system" fn(i32)>) {
    REGISTERED.fetch_add(1, Ordering::SeqCst);
    CALLBACK.store(cb.map_or(std::ptr::null_mut(), |f| f as *mut c_void), Ordering::SeqCst);
}
unsafe extern "system" fn unregister(cb: Option<unsafe extern "system" fn(i32)>) {
    assert_eq!(cb.map(|f| f as *mut c_void), Some(CALLBACK.load(Ordering::SeqCst)));
    UNREGISTERED.fetch_add(1, Ordering::SeqCst);
}
unsafe extern "system" fn reserve(count: i32) -> i32 {
    assert_eq!(count, 1);
    7000
}
unsafe extern "system" fn get_split(high: u64, low: u64) -> *mut c_void {
    // IUnityGraphics only; no IUnityGraphicsVulkan on a non-Vulkan renderer.
    if (high, low) == (0x7CBA_0A9C_A4DD_B544, 0x8C5A_D492_6EB1_7B11) {
        GRAPHICS.load(Ordering::SeqCst)
    } else {
        std::ptr::null_mut()
    }
}
unsafe extern "system" fn get_nothing(_h: u64, _l: u64) -> *mut c_void {
    std::ptr::null_mut()
}

fn status() -> WetHairUnityStatus {
    let mut st: WetHairUnityStatus = unsafe { std::mem::zeroed() };
    st.struct_size = std::mem::size_of::<WetHairUnityStatus>() as u32;
    assert_eq!(unsafe { wethair_unity_get_status(&mut st) }, WetHairResult::WETHAIR_OK);
    st
}

fn reason(st: &WetHairUnityStatus) -> String {
    let n = st.reason.iter().position(|&b| b == 0).unwrap_or(256);
    String::from_utf8_lossy(&st.reason[..n]).into_owned()
}

/// A CPU simulation made through the Unity entry, stepped by the render event, destroyed.
unsafe fn simulate_through_render_event(event_base: i32) {
    let mut groom = std::ptr::null_mut();
    assert_eq!(
        wethair_groom_create_paper_scene(100, 6, &mut groom),
        WetHairResult::WETHAIR_OK
    );
    let mut desc: WetHairSimDesc = std::mem::zeroed();
    wethair_sim_desc_default(&mut desc);
    desc.groom = groom;
    desc.backend = 1; // CPU: this test is about the plugin, not a device
    desc.threads = 1;
    let mut sim = std::ptr::null_mut();
    assert_eq!(wethair_unity_sim_create(&desc, &mut sim), WetHairResult::WETHAIR_OK);
    wethair_groom_destroy(groom);
    let event = wethair_unity_get_render_event_func().expect("render event");
    let mut step = WetHairUnityStep {
        struct_size: std::mem::size_of::<WetHairUnityStep>() as u32,
        dt: 1.0 / 60.0,
        sim,
        result: 99,
        reserved: 0,
    };
    for _ in 0..3 {
        event(event_base, &mut step as *mut _ as *mut c_void);
        assert_eq!(step.result, WetHairResult::WETHAIR_OK as u32);
    }
    // Another plugin's event id is ignored; a NaN dt is reported in the struct.
    step.result = 99;
    event(event_base + 1, &mut step as *mut _ as *mut c_void);
    assert_eq!(step.result, 99);
    step.dt = f32::NAN;
    event(event_base, &mut step as *mut _ as *mut c_void);
    assert_eq!(step.result, WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT as u32);
    event(event_base, std::ptr::null_mut());
    let mut stats: WetHairStats = std::mem::zeroed();
    stats.struct_size = std::mem::size_of::<WetHairStats>() as u32;
    assert_eq!(wethair_sim_get_stats(sim, &mut stats), WetHairResult::WETHAIR_OK);
    assert_eq!(stats.steps, 3);
    wethair_sim_destroy(sim);
}

/// Set in the child process that runs the leak check alone.
const ALONE: &str = "WETHAIR_UNITY_LEAK_CHECK_ALONE";

#[test]
fn plugin_loads_falls_back_and_unloads_without_leaks() {
    // The byte counter sees every thread of the process, and the other tests of this binary
    // allocate while they run beside this one; so the check runs in a child process of this
    // same test binary with only this test selected, where nothing else allocates.
    if crate::common::ran_alone("unity::plugin_loads_falls_back_and_unloads_without_leaks", ALONE) {
        return;
    }
    unsafe {
        // Warm up what allocates once per process (thread-locals, the error store, pools).
        let st = status();
        assert_eq!(st.loaded, 0);
        simulate_through_render_event(0);
        cycle();
        // A leak grows every cycle; a worker thread's late free (a simulation's pool ends as
        // it is joined) can land either side of a reading once. So: some cycle must end where
        // it began, out of three.
        let mut deltas = Vec::new();
        for _ in 0..3 {
            let before = LIVE.load(Ordering::SeqCst);
            cycle();
            let d = LIVE.load(Ordering::SeqCst) - before;
            if d == 0 {
                return;
            }
            deltas.push(d);
        }
        panic!("every load/unload cycle left bytes allocated: {deltas:?}");
    }
}

/// No interfaces; no graphics interface; a D3D11 device with a simulation stepped by the render
/// event, its shutdown, and a Vulkan device without the interception; each unloaded.
unsafe fn cycle() {
    REGISTERED.store(0, Ordering::SeqCst);
    UNREGISTERED.store(0, Ordering::SeqCst);
    RENDERER.store(2, Ordering::SeqCst);

    // 1. No interfaces at all.
    UnityPluginLoad(std::ptr::null_mut());
    let st = status();
    assert_eq!((st.loaded, st.renderer, st.on_unity_device), (1, -1, 0));
    UnityPluginUnload();
    assert_eq!(status().loaded, 0);

    // 2. A registry without a graphics interface (no graphics device: batch mode).
    let mut none = IUnityInterfaces {
        get_interface: None,
        register_interface: None,
        get_interface_split: Some(get_nothing),
        register_interface_split: None,
    };
    UnityPluginLoad(&mut none);
    let st = status();
    assert_eq!((st.loaded, st.renderer, st.on_unity_device), (1, -1, 0));
    UnityPluginUnload();

    // 3. A graphics device reporting D3D11 (2): not Vulkan, so simulations use their own.
    let mut graphics = IUnityGraphics {
        get_renderer: Some(get_renderer),
        register_device_event_callback: Some(register),
        unregister_device_event_callback: Some(unregister),
        reserve_event_id_range: Some(reserve),
    };
    GRAPHICS.store(&mut graphics as *mut _ as *mut c_void, Ordering::SeqCst);
    let mut interfaces = IUnityInterfaces {
        get_interface: None,
        register_interface: None,
        get_interface_split: Some(get_split),
        register_interface_split: None,
    };
    UnityPluginLoad(&mut interfaces);
    assert_eq!(REGISTERED.load(Ordering::SeqCst), 1);
    let st = status();
    assert_eq!(
        (st.loaded, st.renderer, st.on_unity_device, st.event_id_base),
        (1, 2, 0, 7000)
    );
    assert!(reason(&st).contains("not Vulkan"), "{}", reason(&st));
    simulate_through_render_event(7000);
    // Unity's shutdown event, then a device that comes back as Vulkan without the
    // interception (the plugin was not loaded at startup): still the fallback, with why.
    let cb: unsafe extern "system" fn(i32) = std::mem::transmute(CALLBACK.load(Ordering::SeqCst));
    cb(1);
    assert_eq!(status().renderer, -1);
    RENDERER.store(21, Ordering::SeqCst);
    cb(0);
    let st = status();
    assert_eq!((st.renderer, st.on_unity_device), (21, 0));
    assert!(
        reason(&st).contains("Vulkan instance data is not available"),
        "{}",
        reason(&st)
    );
    UnityPluginUnload();
    assert_eq!(UNREGISTERED.load(Ordering::SeqCst), 1);
    assert_eq!(status().loaded, 0);
    GRAPHICS.store(std::ptr::null_mut(), Ordering::SeqCst);
}
