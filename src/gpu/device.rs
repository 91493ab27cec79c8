//! Finding an adapter and opening a device, with wgpu's errors turned into ours.
//!
//! wgpu reports validation errors, out-of-memory and device loss through callbacks whose
//! defaults panic; [`GpuDevice`] installs handlers that record the first failure instead, and
//! every step checks it, so a failure becomes [`Error::Device`] and nothing panics.

use crate::error::{Error, Result};
use std::future::Future;
use std::sync::{Arc, Mutex};

/// A wgpu device and queue with the error state its callbacks fill.
#[derive(Debug)]
pub struct GpuDevice {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter's description (name, backend, driver).
    pub info: wgpu::AdapterInfo,
    /// The limits the device was opened with.
    pub limits: wgpu::Limits,
    /// Whether GPU timestamp queries are enabled.
    pub timestamps: bool,
    /// Whether timestamps may also be written inside a compute pass (per-stage timing).
    pub pass_timestamps: bool,
    /// Whether shaders may add to 64-bit integers atomically (the particles' reaction sums
    /// then take one add a component, with no carry to read back; adhesion.wgsl).
    pub atomic64: bool,
    failure: Arc<Mutex<Option<String>>>,
    /// The semaphores shared with the host when the device is the host's (feature `vulkan`).
    #[cfg(feature = "vulkan")]
    pub shared: Option<crate::gpu::vulkan::SharedSync>,
    /// Held from `drop` until every wgpu object above is gone (they touch the host's queue).
    #[cfg(feature = "vulkan")]
    queue_guard: Option<crate::gpu::vulkan::QueueGuard>,
}

#[cfg(feature = "vulkan")]
impl Drop for GpuDevice {
    fn drop(&mut self) {
        // Finish our work under the host's queue lock; the fields then drop in order (the
        // wgpu queue waits for idle on drop), and the guard, last, unlocks.
        if let Some(lock) = self.shared.as_ref().and_then(|s| s.lock.clone()) {
            self.queue_guard = Some(lock.guard());
        }
        let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
    }
}

impl GpuDevice {
    /// Opens a device on the adapter `WGPU_ADAPTER_NAME` names (a case-insensitive substring),
    /// or else the high-performance one, among the backends `WGPU_BACKEND` allows. With
    /// `allow_software` false, a CPU adapter (lavapipe, WARP) is refused before a device is
    /// opened on it.
    pub fn open(allow_software: bool) -> Result<GpuDevice> {
        let adapter = pick_adapter(instance())?;
        let info = adapter.get_info();
        if !allow_software && info.device_type == wgpu::DeviceType::Cpu {
            return Err(Error::Unsupported(format!(
                "only a software adapter was found ({} ({:?})), which is slower than the CPU backend",
                info.name, info.backend
            )));
        }
        let (features, limits) = wanted(adapter.features(), &adapter.limits());
        let desc = descriptor(features, &limits);
        let (device, queue) = block_on(adapter.request_device(&desc))
            .map_err(|e| Error::Device(format!("could not open a device on {}: {e}", info.name)))?;
        Ok(Self::from_parts(info, device, queue, limits, features))
    }

    /// Wraps an opened device: installs the error handlers.
    pub(crate) fn from_parts(
        info: wgpu::AdapterInfo,
        device: wgpu::Device,
        queue: wgpu::Queue,
        limits: wgpu::Limits,
        features: wgpu::Features,
    ) -> GpuDevice {
        let timestamps = features.contains(wgpu::Features::TIMESTAMP_QUERY);
        let pass_timestamps = timestamps && features.contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);
        let atomic64 = features.contains(ATOMIC64);
        let failure: Arc<Mutex<Option<String>>> = Arc::default();
        let sink = failure.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| record(&sink, &e.to_string())));
        let sink = failure.clone();
        device.set_device_lost_callback(move |reason, msg| record(&sink, &format!("device lost ({reason:?}): {msg}")));
        GpuDevice {
            device,
            queue,
            info,
            limits,
            timestamps,
            pass_timestamps,
            atomic64,
            failure,
            #[cfg(feature = "vulkan")]
            shared: None,
            #[cfg(feature = "vulkan")]
            queue_guard: None,
        }
    }

    /// Submits one command buffer. On a host's device this holds the host's queue lock and
    /// adds the shared semaphores (see [`crate::gpu::vulkan::SharedSync`]); `wrote_vertices`
    /// says whether it writes the vertex buffer the host draws from.
    pub fn submit(&self, commands: wgpu::CommandBuffer, wrote_vertices: bool) {
        #[cfg(feature = "vulkan")]
        if let Some(s) = &self.shared {
            let _held = s.lock.as_ref().map(|l| l.guard());
            s.stage(&self.queue, wrote_vertices);
            self.queue.submit([commands]);
            return;
        }
        let _ = wrote_vertices;
        self.queue.submit([commands]);
    }

    /// The adapter's name and backend, as stats report it.
    pub fn adapter_name(&self) -> String {
        format!("{} ({:?})", self.info.name, self.info.backend)
    }

    /// The first failure the device reported, if any.
    pub fn failure(&self) -> Option<String> {
        self.failure
            .lock()
            .map_or(Some("device error state poisoned".into()), |f| f.clone())
    }

    /// Fails with [`Error::Device`] when the device has reported a failure.
    pub fn check(&self) -> Result<()> {
        match self.failure() {
            Some(m) => Err(Error::Device(m)),
            None => Ok(()),
        }
    }

    /// Waits for all submitted work; a failed wait is a device failure.
    pub fn wait(&self) -> Result<()> {
        if let Err(e) = self.device.poll(wgpu::PollType::wait_indefinitely()) {
            record(&self.failure, &format!("waiting for the GPU failed: {e}"));
        }
        self.check()
    }

    /// Destroys the device, as a lost device would be (tests of the error path).
    pub fn lose(&self) {
        self.device.destroy();
        let _ = self.device.poll(wgpu::PollType::Poll);
        record(&self.failure, "device lost: destroyed on request");
    }
}

/// 64-bit integers with every atomic operation on them.
const ATOMIC64: wgpu::Features = wgpu::Features::SHADER_INT64.union(wgpu::Features::SHADER_INT64_ATOMIC_ALL_OPS);

/// The features and limits wethair asks of an adapter: timestamps where offered (also inside
/// passes, for per-stage timing), 64-bit atomics where offered (unless
/// `WETHAIR_GPU_NO_ATOMIC64` is set: tests run the 32-bit form that way), and storage
/// bindings as large as the adapter allows (large grooms need them).
pub(crate) fn wanted(have: wgpu::Features, have_limits: &wgpu::Limits) -> (wgpu::Features, wgpu::Limits) {
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: have_limits.max_storage_buffer_binding_size,
        max_buffer_size: have_limits.max_buffer_size,
        ..wgpu::Limits::default()
    };
    let timestamps = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES;
    let mut features = have & timestamps;
    if have.contains(ATOMIC64) && std::env::var_os("WETHAIR_GPU_NO_ATOMIC64").is_none() {
        features |= ATOMIC64;
    }
    (features, limits)
}

/// Whether the particles gather eq. 2's reactions (`reactions.wgsl`) rather than the hair
/// points adding them by atomics: `WETHAIR_GPU_REACTIONS=gather`. Both give the same bits
/// (`tests/gpu.rs`); the scatter form stays the default until the gather is timed on a GPU.
pub fn gathers_reactions() -> bool {
    std::env::var("WETHAIR_GPU_REACTIONS").is_ok_and(|v| v == "gather")
}

/// The device descriptor for [`wanted`]'s features and limits.
pub(crate) fn descriptor(features: wgpu::Features, limits: &wgpu::Limits) -> wgpu::DeviceDescriptor<'static> {
    wgpu::DeviceDescriptor {
        label: Some("wethair"),
        required_features: features,
        required_limits: limits.clone(),
        ..Default::default()
    }
}

fn record(sink: &Mutex<Option<String>>, msg: &str) {
    if let Ok(mut f) = sink.lock() {
        f.get_or_insert_with(|| msg.to_string());
    }
}

/// The process's one wgpu instance, made on the first device's opening (reading `WGPU_BACKEND`
/// then) and kept until the process ends.
///
/// Why not one per device: dropping a device's own instance destroys the process's last
/// Vulkan instance, on which the Vulkan loader unloads the driver, and the next device loads it
/// again. NVIDIA's driver cannot be loaded that often: each load takes static TLS that its
/// unload does not give back: with driver 580.159 the 31st instance in one process on an H200,
/// and the 30th on an H100, found no driver (the loader: "libnvidia-tls.so.580.159.04: cannot
/// allocate memory in static TLS block"; `device_cycles instance 40`). One instance is also
/// what wgpu expects of an application; devices opened on it still close with their
/// simulations.
pub fn instance() -> &'static wgpu::Instance {
    static INSTANCE: std::sync::OnceLock<wgpu::Instance> = std::sync::OnceLock::new();
    INSTANCE.get_or_init(|| wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env()))
}

/// The adapter named by `WGPU_ADAPTER_NAME`, else the one wgpu prefers for performance.
fn pick_adapter(instance: &wgpu::Instance) -> Result<wgpu::Adapter> {
    let adapters = block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    if let Ok(want) = std::env::var("WGPU_ADAPTER_NAME") {
        let want = want.to_lowercase();
        let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
        return adapters
            .into_iter()
            .find(|a| a.get_info().name.to_lowercase().contains(&want))
            .ok_or_else(|| {
                Error::Device(format!(
                    "no adapter matches WGPU_ADAPTER_NAME={want:?} (found {names:?})"
                ))
            });
    }
    let opts = wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    };
    block_on(instance.request_adapter(&opts)).map_err(|e| {
        Error::Device(format!(
            "no GPU adapter found ({e}); on Linux without a GPU install Mesa's lavapipe \
             (mesa-vulkan-drivers)"
        ))
    })
}

/// Runs a future to completion on this thread. wgpu's native futures are ready once the
/// device has been polled, so a spin with yields is all they need.
pub fn block_on<F: Future>(f: F) -> F::Output {
    use std::task::{Context, Poll, RawWaker, RawWakerVTable, Waker};
    fn raw() -> RawWaker {
        fn clone(_: *const ()) -> RawWaker {
            raw()
        }
        fn noop(_: *const ()) {}
        static VTABLE: RawWakerVTable = RawWakerVTable::new(clone, noop, noop, noop);
        RawWaker::new(std::ptr::null(), &VTABLE)
    }
    // SAFETY: the vtable's functions do nothing and never touch the data pointer.
    let waker = unsafe { Waker::from_raw(raw()) };
    let mut cx = Context::from_waker(&waker);
    let mut f = std::pin::pin!(f);
    loop {
        if let Poll::Ready(v) = f.as_mut().poll(&mut cx) {
            return v;
        }
        std::thread::yield_now();
    }
}
