//! The shared frame's synchronisation: two timeline semaphores of ours (`ready`, signalled by
//! every submission that writes the vertex buffer; `release`, signalled by the host when it has
//! read it), and what a host is handed (`SharedFrame`, `SharedWater`).

use super::*;

/// The values of the shared timeline semaphores.
#[derive(Debug, Default)]
struct SyncState {
    /// Value `ready` reaches when the last vertex write completes.
    ready: u64,
    /// A value the host promised to signal on `release` before we write the vertices again.
    release_wait: Option<u64>,
}

/// Two timeline semaphores made on the host's device: `ready`, which we signal when a
/// submission that wrote the vertex buffer completes, and `release`, which the host signals
/// when its reads of a frame it acquired are done; our next submission waits for it.
pub struct SharedSync {
    device: ash::Device,
    /// Signalled by wethair.
    pub ready: vk::Semaphore,
    /// Signalled by the host.
    pub release: vk::Semaphore,
    /// The host's queue lock.
    pub lock: Option<Arc<QueueLock>>,
    state: Mutex<SyncState>,
}

impl std::fmt::Debug for SharedSync {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SharedSync")
            .field("ready", &self.ready)
            .field("release", &self.release)
            .finish()
    }
}

impl SharedSync {
    pub(super) fn new(device: ash::Device, lock: Option<Arc<QueueLock>>) -> Result<Self> {
        let mut kind = vk::SemaphoreTypeCreateInfo::default()
            .semaphore_type(vk::SemaphoreType::TIMELINE)
            .initial_value(0);
        let info = vk::SemaphoreCreateInfo::default().push_next(&mut kind);
        let make = |what: &str| {
            // SAFETY: a valid device; the info is complete.
            unsafe { device.create_semaphore(&info, None) }
                .map_err(|e| Error::Device(format!("creating the {what} timeline semaphore: {e}")))
        };
        let ready = make("ready")?;
        let release = match make("release") {
            Ok(r) => r,
            Err(e) => {
                // SAFETY: made above, never used.
                unsafe { device.destroy_semaphore(ready, None) };
                return Err(e);
            }
        };
        Ok(SharedSync {
            device,
            ready,
            release,
            lock,
            state: Mutex::default(),
        })
    }

    /// When the submission writes the vertices: the pending wait on `release` (the host's
    /// reads of the frame it acquired) and a signal of `ready`'s next value, staged on wgpu's
    /// next submission on `queue`. Submissions that only read the buffer need neither.
    pub(crate) fn stage(&self, queue: &wgpu::Queue, wrote_vertices: bool) {
        if !wrote_vertices {
            return;
        }
        let Ok(mut st) = self.state.lock() else { return };
        // SAFETY: the queue is a Vulkan queue; the semaphores are ours, on its device.
        let Some(hal) = (unsafe { queue.as_hal::<Vulkan>() }) else {
            return;
        };
        if let Some(v) = st.release_wait.take() {
            hal.add_wait_semaphore(self.release, Some(v), vk::PipelineStageFlags::COMPUTE_SHADER);
        }
        st.ready += 1;
        hal.add_signal_semaphore(self.ready, Some(st.ready));
    }

    /// The frame the host may now read: `ready`'s value to wait for, and the value it must
    /// signal on `release` when done (our next write waits for it).
    pub fn acquire(&self) -> (u64, u64) {
        let mut st = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let v = st.ready;
        st.release_wait = Some(v);
        (v, v)
    }
}

impl Drop for SharedSync {
    fn drop(&mut self) {
        // SAFETY: the GPU is idle (GpuDevice::drop waited) and the semaphores are ours.
        unsafe {
            self.device.destroy_semaphore(self.ready, None);
            self.device.destroy_semaphore(self.release, None);
        }
    }
}

/// The host-visible description of the water buffers: raw handles as integers.
#[derive(Clone, Copy, Debug)]
pub struct SharedWater {
    /// The positions' `VkBuffer`: a vec4 (xyz, w = 1) per particle held.
    pub buffer: u64,
    /// Most particles it holds.
    pub capacity: u32,
    /// The `VkBuffer` holding a `VkDrawIndirectCommand` (vertexCount = particles held).
    pub draw_buffer: u64,
}

/// The host-visible description of the vertex buffer: raw handles as integers.
#[derive(Clone, Copy, Debug)]
pub struct SharedFrame {
    /// The `VkBuffer`.
    pub buffer: u64,
    /// Size in bytes.
    pub size: u64,
    /// `ready` semaphore and the value to wait for.
    pub ready_semaphore: u64,
    /// The value.
    pub ready_value: u64,
    /// `release` semaphore and the value to signal.
    pub release_semaphore: u64,
    /// The value.
    pub release_value: u64,
}

/// The raw `VkBuffer` behind a wgpu buffer.
pub fn raw_buffer(buf: &wgpu::Buffer) -> Option<u64> {
    use ash::vk::Handle;
    // SAFETY: the guard is dropped at once; the handle is not destroyed by us.
    unsafe { buf.as_hal::<Vulkan>().map(|b| b.raw_handle().as_raw()) }
}

/// Semaphore handles as integers.
pub fn raw_semaphore(s: vk::Semaphore) -> u64 {
    use ash::vk::Handle;
    s.as_raw()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn feature_names_come_from_ash_debug() {
        let core = vk::PhysicalDeviceFeatures::default()
            .robust_buffer_access(true)
            .sampler_anisotropy(true);
        assert_eq!(
            set_members(&format!("{core:?}")),
            ["robust_buffer_access", "sampler_anisotropy"]
        );
        let mut timeline = vk::PhysicalDeviceTimelineSemaphoreFeatures::default().timeline_semaphore(true);
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default().subgroup_size_control(true);
        let f2 = vk::PhysicalDeviceFeatures2::default()
            .features(core)
            .push_next(&mut timeline)
            .push_next(&mut v13);
        // SAFETY: a valid chain built just above.
        let names = unsafe { enabled_names(&f2 as *const _ as *const c_void) };
        assert_eq!(
            names,
            [
                "robust_buffer_access",
                "sampler_anisotropy",
                "subgroup_size_control",
                "timeline_semaphore"
            ]
        );
        assert_eq!(
            camel("shader_zero_initialize_workgroup_memory"),
            "shaderZeroInitializeWorkgroupMemory"
        );
    }
}
