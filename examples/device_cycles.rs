//! Opens and drops GPU devices in a loop and prints the process's footprint (file
//! descriptors, threads, resident memory) as it goes, to find what a driver keeps of each:
//! `cargo run --release --example device_cycles -- <mode> [cycles]`, where mode is
//! `instance` (a wgpu instance of its own and its adapter list, the instance dropped each
//! cycle: on NVIDIA's driver this finds no adapter after about thirty), `device`
//! (`GpuDevice::open`, on the process's one instance), `shared` (devices opened on one
//! adapter) or `sim` (a GPU simulation created, stepped, read and dropped).
//! `-- <mode> <cycles> thread` runs the cycles on a spawned thread, as a test harness runs a
//! test. It stops at the first
//! cycle that finds no adapter and says which. Linux only (it reads /proc).
use wethair::gpu::device::{block_on, GpuDevice};
use wethair::{groom::paper_scene, Backend, SimParams, Simulation};

/// (descriptors, threads, resident KiB) of this process.
fn footprint() -> (usize, usize, u64) {
    let count = |d: &str| std::fs::read_dir(d).map(|r| r.count()).unwrap_or(0);
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let rss = status
        .lines()
        .find(|l| l.starts_with("VmRSS:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    (count("/proc/self/fd"), count("/proc/self/task"), rss)
}

fn main() {
    if std::env::args().nth(3).as_deref() == Some("thread") {
        std::thread::spawn(cycles).join().expect("the cycles' thread");
    } else {
        cycles();
    }
}

fn cycles() {
    let mode = std::env::args().nth(1).unwrap_or_else(|| "sim".into());
    let cycles: usize = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(60);
    let groom = paper_scene(64, 6).expect("groom");
    let shared_adapter = (mode == "shared").then(|| {
        block_on(wethair::gpu::device::instance().request_adapter(&wgpu::RequestAdapterOptions::default()))
            .expect("adapter")
    });
    println!("mode {mode}: before {:?}", footprint());
    for c in 0..cycles {
        let ok = match mode.as_str() {
            "instance" => {
                let i = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
                !block_on(i.enumerate_adapters(wgpu::Backends::all())).is_empty()
            }
            "device" => GpuDevice::open(true).map_err(|e| println!("{e}")).is_ok(),
            "shared" => {
                let a = shared_adapter.as_ref().expect("adapter");
                block_on(a.request_device(&wgpu::DeviceDescriptor::default()))
                    .map_err(|e| println!("{e}"))
                    .is_ok()
            }
            _ => {
                let params = SimParams {
                    backend: Backend::GPU,
                    ..SimParams::paper()
                };
                match Simulation::new(&groom, params) {
                    Ok(mut sim) => {
                        sim.step(1.0 / 60.0).expect("step");
                        sim.positions().len() == groom.point_count()
                    }
                    Err(e) => {
                        println!("{e}");
                        false
                    }
                }
            }
        };
        if !ok {
            println!("cycle {c}: no adapter or device; {:?}", footprint());
            std::process::exit(1);
        }
        if c % 5 == 4 {
            println!("cycle {}: {:?}", c + 1, footprint());
        }
    }
    println!("{cycles} cycles, all opened: {:?}", footprint());
}
