//! The wet model through the C ABI (issue 14): `held_water` and `wind` in `WetHairSimDesc`,
//! `wethair_sim_soak`, `wethair_sim_set_wind`, and the exact water ledger in `WetHairStats`;
//! bad values refused by name with nothing written, older struct sizes still accepted.

use std::ptr::null_mut;
use wethair::ffi::*;
use WetHairResult::*;

use crate::common::{last_error, serial};

fn paper(strands: u32) -> *mut WetHairGroom {
    let mut g = null_mut();
    assert_eq!(
        unsafe { wethair_groom_create_paper_scene(strands, 6, &mut g) },
        WETHAIR_OK
    );
    g
}

/// The current desc's defaults on the CPU, with held water switched on.
fn wet_desc(groom: *const WetHairGroom) -> WetHairSimDesc {
    let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
    let size = std::mem::size_of::<WetHairSimDesc>() as u32;
    assert_eq!(unsafe { wethair_sim_desc_init(d.as_mut_ptr(), size) }, WETHAIR_OK);
    let mut d = unsafe { d.assume_init() };
    assert_eq!(d.held_water.enabled, 0, "off by default");
    assert_eq!(d.wind.velocity, [0.0; 3], "calm by default");
    d.groom = groom;
    d.backend = wethair::Backend::CPU as u32;
    d.held_water.enabled = 1;
    d.held_water.dry_time = 2.0;
    d
}

/// A simulation from `d`, which must be accepted (the error in the message if not).
fn create(d: &WetHairSimDesc) -> *mut WetHairSim {
    let mut s = null_mut();
    assert_eq!(unsafe { wethair_sim_create(d, &mut s) }, WETHAIR_OK, "{}", last_error());
    s
}

/// `wethair_sim_get_counters`, checked against `st` (the same frame's stats): every counter
/// the same, every measure -1.
fn counters_match(sim: *const WetHairSim, st: &WetHairStats) {
    let mut c = std::mem::MaybeUninit::<WetHairStats>::zeroed();
    let c = unsafe {
        (*c.as_mut_ptr()).struct_size = std::mem::size_of::<WetHairStats>() as u32;
        assert_eq!(wethair_sim_get_counters(sim, c.as_mut_ptr()), WETHAIR_OK);
        c.assume_init()
    };
    let measures = |s: &WetHairStats| [s.clumping, s.clumping_along, s.error_estimate, s.error_estimate_max];
    assert_eq!(measures(&c), [-1.0; 4], "counters take no measure");
    assert!(st.clumping > 0.0 && st.clumping_along > 0.0, "stats measure: {st:?}");
    let counted = WetHairStats {
        clumping: st.clumping,
        clumping_along: st.clumping_along,
        error_estimate: st.error_estimate,
        error_estimate_max: st.error_estimate_max,
        ..c
    };
    assert_eq!(format!("{counted:?}"), format!("{st:?}"), "the counters are the stats'");
}

fn stats(sim: *const WetHairSim) -> WetHairStats {
    let mut st = std::mem::MaybeUninit::<WetHairStats>::zeroed();
    unsafe {
        (*st.as_mut_ptr()).struct_size = std::mem::size_of::<WetHairStats>() as u32;
        assert_eq!(wethair_sim_get_stats(sim, st.as_mut_ptr()), WETHAIR_OK);
        st.assume_init()
    }
}

#[test]
fn the_ledger_reaches_c_hosts_exactly() {
    assert_eq!(WETHAIR_WATER_QUANTUM_KG, 1e-12);
    let header = include_str!("../include/wethair.h");
    assert!(header.contains("#define WETHAIR_WATER_QUANTUM_KG 1e-12"));
    ledger_through_c(wethair::Backend::CPU);
}

/// The full wet model (liquid bridges included) on the GPU backend through the C ABI, where
/// an adapter exists (always under `WETHAIR_REQUIRE_GPU=1`): the same exact ledger.
#[test]
fn the_full_wet_model_runs_on_the_gpu_through_c() {
    let _serial = serial();
    ledger_through_c(wethair::Backend::GPU);
}

/// Soak, wind, two particles and 120 frames through the C ABI on `backend`: the ledger
/// balances every frame, the hair holds water and some evaporated; older hosts' stats get no
/// ledger. A GPU that cannot start is a failure only under `WETHAIR_REQUIRE_GPU=1`.
fn ledger_through_c(backend: wethair::Backend) {
    let g = paper(200);
    let mut s = null_mut();
    let mut desc = wet_desc(g);
    desc.backend = backend as u32;
    assert!(
        desc.held_water.bridge_tension > 0.0,
        "the full model: bridges on by default"
    );
    let r = unsafe { wethair_sim_create(&desc, &mut s) };
    if r != WETHAIR_OK && backend == wethair::Backend::GPU && std::env::var("WETHAIR_REQUIRE_GPU").as_deref() != Ok("1")
    {
        eprintln!("no GPU adapter, GPU test not run: {}", last_error());
        unsafe { wethair_groom_destroy(g) };
        return;
    }
    assert_eq!(r, WETHAIR_OK, "{}", last_error());
    assert_eq!(stats(s).backend, backend as u32);
    assert_eq!(unsafe { wethair_sim_soak(s, 0.8) }, WETHAIR_OK);
    let wind = WetHairWind {
        velocity: [2.0, 0.0, 0.0],
        gust: 0.3,
        seed: 9,
    };
    assert_eq!(unsafe { wethair_sim_set_wind(s, &wind) }, WETHAIR_OK);
    let pos = [0.0f32, 0.0, 0.25, 0.01, 0.0, 0.25];
    assert_eq!(
        unsafe { wethair_sim_add_water(s, pos.as_ptr(), std::ptr::null(), 2) },
        WETHAIR_OK
    );
    for _ in 0..120 {
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
        let st = stats(s);
        counters_match(s, &st);
        assert_eq!(
            st.water_added,
            st.water_in_particles + st.water_held + st.water_left + st.water_evaporated,
            "balanced every frame"
        );
    }
    let st = stats(s);
    assert!(st.water_held > 0 && st.water_evaporated > 0, "{st:?}");
    // An older host's 64-byte stats get no ledger, and no write past their size.
    let mut old = [0xa5u8; 112];
    old[..4].copy_from_slice(&64u32.to_ne_bytes());
    assert_eq!(
        unsafe { wethair_sim_get_stats(s, old.as_mut_ptr() as *mut WetHairStats) },
        WETHAIR_OK
    );
    assert!(old[64..].iter().all(|&b| b == 0xa5), "written past the host's 64 bytes");
    let mut old = [0xa5u8; 112];
    old[..4].copy_from_slice(&64u32.to_ne_bytes());
    assert_eq!(
        unsafe { wethair_sim_get_counters(s, old.as_mut_ptr() as *mut WetHairStats) },
        WETHAIR_OK
    );
    assert!(
        old[64..].iter().all(|&b| b == 0xa5),
        "counters written past the host's 64 bytes"
    );
    assert_eq!(
        u64::from_ne_bytes(old[24..32].try_into().unwrap()),
        120,
        "steps counted"
    );
    unsafe {
        wethair_sim_destroy(s);
        wethair_groom_destroy(g);
    }
}

#[test]
fn bad_wet_values_are_refused_by_name_and_write_nothing() {
    let g = paper(20);
    let sentinel = 0x5a5a as *mut WetHairSim;
    let refused = |d: WetHairSimDesc, code: WetHairResult, name: &str| {
        let mut out = sentinel;
        let r = unsafe { wethair_sim_create(&d, &mut out) };
        assert_eq!(r, code, "{name}: {}", last_error());
        assert_eq!(out, sentinel, "{name}: output written on failure");
        assert!(last_error().contains(name), "{name}: {}", last_error());
    };
    let mut d = wet_desc(g);
    d.held_water.enabled = 2;
    refused(d, WETHAIR_ERROR_INVALID_ARGUMENT, "held_water.enabled");
    for (set, name) in [
        (
            (|d: &mut WetHairSimDesc| d.held_water.capacity_ratio = f32::NAN) as fn(&mut WetHairSimDesc),
            "capacity_ratio",
        ),
        (|d| d.held_water.dry_time = -1.0, "dry_time"),
        (|d| d.held_water.absorb_rate = f32::INFINITY, "absorb_rate"),
        (|d| d.held_water.wet_bend_ratio = 1.5, "wet_bend_ratio"),
        (|d| d.held_water.bridge_tension = -0.1, "bridge_tension"),
        (|d| d.held_water.flow_mobility = f32::NAN, "flow_mobility"),
        (|d| d.held_water.drip_mass = 0.0, "drip_mass"),
        (|d| d.held_water_free_ratio = -1.0, "free_ratio"),
        (|d| d.held_water_free_ratio = f32::INFINITY, "free_ratio"),
        (|d| d.held_water_flow_length = 0.0, "flow_length"),
        (|d| d.held_water_flow_length = -0.02, "flow_length"),
        (|d| d.held_water_flow_length = f32::NAN, "flow_length"),
        (|d| d.held_water_flow_length = 2.0, "flow_length"),
        (|d| d.air_drag_length = -0.02, "air_drag_length"),
        (|d| d.air_drag_length = f32::NAN, "air_drag_length"),
        (|d| d.air_drag_length = f32::INFINITY, "air_drag_length"),
        (|d| d.air_drag_length = 2.0, "air_drag_length"),
        (|d| d.water_adhesion_length = -0.02, "adhesion_length"),
        (|d| d.water_adhesion_length = f32::NAN, "adhesion_length"),
        (|d| d.water_adhesion_length = 1.5, "adhesion_length"),
        (|d| d.water_pile_cell = -1.0e-4, "pile cell"),
        (|d| d.water_pile_cell = f32::NAN, "pile cell"),
        (|d| d.water_pile_cell = f32::INFINITY, "pile cell"),
        (|d| d.water_pile_cell = 0.001, "pile_cell"),
        (|d| d.wind.velocity = [f32::NAN, 0.0, 0.0], "wind velocity"),
        (|d| d.wind.gust = -0.5, "gust"),
    ] {
        let mut d = wet_desc(g);
        set(&mut d);
        refused(d, WETHAIR_ERROR_INVALID_ARGUMENT, name);
    }
    // A live simulation refuses a bad wind and a bad soak, and keeps going.
    let mut s = null_mut();
    assert_eq!(unsafe { wethair_sim_create(&wet_desc(g), &mut s) }, WETHAIR_OK);
    let bad = WetHairWind {
        velocity: [1e6, 0.0, 0.0],
        gust: 0.0,
        seed: 0,
    };
    assert_eq!(unsafe { wethair_sim_set_wind(s, &bad) }, WETHAIR_ERROR_INVALID_ARGUMENT);
    assert!(last_error().contains("wind speed"));
    assert_eq!(
        unsafe { wethair_sim_set_wind(s, std::ptr::null()) },
        WETHAIR_ERROR_NULL_POINTER
    );
    assert_eq!(
        unsafe { wethair_sim_set_wind(null_mut(), &bad) },
        WETHAIR_ERROR_NULL_POINTER
    );
    for v in [f32::NAN, -0.1, 10.5] {
        assert_eq!(
            unsafe { wethair_sim_soak(s, v) },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "soak {v}"
        );
    }
    assert_eq!(unsafe { wethair_sim_soak(null_mut(), 0.5) }, WETHAIR_ERROR_NULL_POINTER);
    assert_eq!(stats(s).water_added, 0, "nothing was added by the refused calls");
    assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
    unsafe { wethair_sim_destroy(s) };
    // Without held water, soaking is unsupported and the ledger reads zero.
    let mut d = wet_desc(g);
    d.held_water.enabled = 0;
    let mut s = null_mut();
    assert_eq!(unsafe { wethair_sim_create(&d, &mut s) }, WETHAIR_OK);
    assert_eq!(unsafe { wethair_sim_soak(s, 0.5) }, WETHAIR_ERROR_UNSUPPORTED);
    let st = stats(s);
    assert_eq!((st.water_added, st.water_held), (0, 0));
    unsafe {
        wethair_sim_destroy(s);
        wethair_groom_destroy(g);
    }
}

#[test]
fn an_older_desc_without_the_wet_fields_runs_dry() {
    // A host built before held water passes 152 bytes: the fields past them take their
    // defaults (off, calm), whatever lies beyond its struct.
    let g = paper(20);
    let mut d = wet_desc(g);
    d.struct_size = 152;
    d.held_water.enabled = 7; // beyond the host's struct: never read
    let s = create(&d);
    assert_eq!(unsafe { wethair_sim_soak(s, 0.5) }, WETHAIR_ERROR_UNSUPPORTED);
    unsafe {
        wethair_sim_destroy(s);
        wethair_groom_destroy(g);
    }
}

#[test]
fn the_desc_grows_by_whole_fields_past_every_older_size() {
    // Every field added since a size starts at or after it: 128 (0.1.0), 152 (material),
    // 216 (0.2.0).
    let d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
    let base = d.as_ptr() as usize;
    let at = |p: *const u8| p as usize - base;
    let d = d.as_ptr();
    unsafe {
        assert!(at(std::ptr::addr_of!((*d).spring_model) as *const u8) >= 128);
        assert!(at(std::ptr::addr_of!((*d).held_water) as *const u8) >= 152);
        assert!(at(std::ptr::addr_of!((*d).wind) as *const u8) >= 152);
    }
    unsafe {
        assert!(at(std::ptr::addr_of!((*d).error_estimate_stride) as *const u8) >= 216);
        assert!(at(std::ptr::addr_of!((*d).fixed_step) as *const u8) >= 232);
        assert!(at(std::ptr::addr_of!((*d).guides) as *const u8) >= 296);
        assert!(at(std::ptr::addr_of!((*d).held_water_free_ratio) as *const u8) >= 328);
        assert!(at(std::ptr::addr_of!((*d).held_water_flow_length) as *const u8) >= 336);
        assert!(at(std::ptr::addr_of!((*d).air_drag_length) as *const u8) >= 344);
        assert!(at(std::ptr::addr_of!((*d).water_adhesion_length) as *const u8) >= 344);
        assert!(at(std::ptr::addr_of!((*d).water_pile_cell) as *const u8) >= 360);
        assert!(at(std::ptr::addr_of!((*d).collider_frames) as *const u8) >= 368);
    }
    assert_eq!(std::mem::size_of::<WetHairSimDesc>(), 376, "no padding at the end");
    assert_eq!(std::mem::size_of::<WetHairStats>(), 120);
}

/// The water held between fibres through C (since 0.6.0): 1 kg/kg by default, what a host sets
/// scales what a soaking puts in, and a 0.5.0 host (328 bytes) gets the default whatever lies
/// past its struct.
#[test]
fn the_free_ratio_reaches_c_hosts_and_older_ones_get_the_default() {
    let g = paper(16);
    let added = |free: f32, size: u32| -> u64 {
        let mut d = wet_desc(g);
        assert_eq!(d.held_water_free_ratio, 1.0, "the default");
        d.held_water_free_ratio = free;
        d.struct_size = size;
        let s = create(&d);
        assert_eq!(unsafe { wethair_sim_soak(s, 1.0) }, WETHAIR_OK);
        let a = stats(s).water_added;
        unsafe { wethair_sim_destroy(s) };
        a
    };
    let full = std::mem::size_of::<WetHairSimDesc>() as u32;
    let (at_default, at_capacity) = (added(1.0, full), added(0.0, full));
    // The hold limit is (0.3 + free) kg per kg of hair: 1.3 against 0.3.
    let ratio = at_default as f64 / at_capacity as f64;
    assert!((ratio - 1.3 / 0.3).abs() < 1e-4, "{ratio}");
    assert_eq!(added(f32::NAN, 328), at_default, "a 0.5.0 host takes the default");
    unsafe { wethair_groom_destroy(g) };
}

/// The length flow's mobility is quoted over, through C (since 0.7.0): 0.02 m by default, and
/// a 0.6.0 host (336 bytes) gets the default whatever lies past its struct. A strand soaked
/// past its hold limits sheds the same in a second with the default and from a 0.6.0 host,
/// and more where the host quotes the same mobility over a longer length (faster water).
#[test]
fn the_flow_length_reaches_c_hosts_and_older_ones_get_the_default() {
    let g = paper(16);
    let shed = |length: f32, size: u32| -> u64 {
        let mut d = wet_desc(g);
        assert_eq!(d.held_water_flow_length, 0.02, "the default");
        d.held_water_flow_length = length;
        // Eq. 2 per point, as a host older than 0.8.0 gets it (its drops pull the hair).
        d.water_adhesion_length = 0.0;
        d.struct_size = size;
        let s = create(&d);
        assert_eq!(unsafe { wethair_sim_soak(s, 2.0) }, WETHAIR_OK);
        for _ in 0..30 {
            assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
        }
        let st = stats(s);
        unsafe { wethair_sim_destroy(s) };
        st.water_added - st.water_held
    };
    let full = std::mem::size_of::<WetHairSimDesc>() as u32;
    let at_default = shed(0.02, full);
    assert!(at_default > 0, "a strand soaked past its hold limits drips");
    assert_eq!(shed(f32::NAN, 336), at_default, "a 0.6.0 host takes the default");
    let faster = shed(0.08, full);
    assert!(
        faster > at_default,
        "four times the speed sheds more: {faster} vs {at_default}"
    );
    unsafe { wethair_groom_destroy(g) };
}

/// The vertices of the 16 paper strands of `s` after `frames` steps of 1/60 s (7 floats a
/// vertex, position first); destroys `s`.
fn stepped_vertices(s: *mut WetHairSim, frames: usize) -> Vec<f32> {
    for _ in 0..frames {
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
    }
    let mut v = vec![0.0f32; 16 * 6 * 7];
    let mut written = 0usize;
    let r = unsafe { wethair_sim_get_vertex_buffer(s, v.as_mut_ptr(), v.len(), &mut written) };
    assert_eq!(r, WETHAIR_OK, "{}", last_error());
    unsafe { wethair_sim_destroy(s) };
    v
}

/// The length of hair the air drag is quoted over, through C (since 0.8.0):
/// `wethair_sim_desc_init` gives 0.02 m, the 0.1.0 defaults 0 (every point takes `air_drag`,
/// the paper's), and a 0.7.0 host (344 bytes) gets 0 whatever lies past its struct, so it runs
/// as it did. A steady wind blows the paper strands' tips the same from a 0.7.0 host as with 0
/// set; quoted over 2 cm (the strands' segment) the tips take half, so they are blown less
/// (0.036 m against 0.052 after two seconds). (tests/material.rs checks the law itself.)
#[test]
fn the_drag_length_reaches_c_hosts_and_older_ones_get_the_default() {
    let old = WetHairSimDesc::default_values();
    assert_eq!(old.air_drag_length, 0.0, "the paper's default, and an older host's");
    let g = paper(16);
    // The tips' mean x after two seconds (position first, 7 floats a vertex).
    let tips = |length: f32, size: u32, wind: f32| -> f32 {
        let mut d = wet_desc(g);
        assert_eq!(d.air_drag_length, 0.02, "init's default");
        d.held_water.enabled = 0;
        d.air_drag = 2.0e-3;
        d.wind.velocity = [wind, 0.0, 0.0];
        d.air_drag_length = length;
        d.struct_size = size;
        let s = create(&d);
        let v = stepped_vertices(s, 120);
        (0..16).map(|k| v[(k * 6 + 5) * 7]).sum::<f32>() / 16.0
    };
    // How far a 3 m/s wind moves them from where they hang in still air.
    let blown = |length: f32, size: u32| tips(length, size, 3.0) - tips(length, size, 0.0);
    let full = std::mem::size_of::<WetHairSimDesc>() as u32;
    let per_point = blown(0.0, full);
    assert_eq!(
        blown(f32::NAN, 344).to_bits(),
        per_point.to_bits(),
        "a 0.7.0 host: per point"
    );
    let at_segment = blown(0.02, full);
    assert!(
        0.0 < at_segment && at_segment < per_point,
        "tips blown {per_point} m per point, {at_segment} m over 2 cm"
    );
    unsafe { wethair_groom_destroy(g) };
}

/// The length of hair eq. 2's pull is quoted over, through C (since 0.8.0): 0.02 m from
/// `wethair_sim_desc_init`, 0 (every point pulls alike, the paper's) in the 0.1.0 defaults and
/// for a 0.7.0 host (344 bytes) whatever lies past its struct. Drops among the paper strands
/// move them alike from a 0.7.0 host and with 0 set, and otherwise over 2 cm (their roots and
/// tips pull half as hard). (tests/material.rs checks the law itself.)
#[test]
fn the_adhesion_length_reaches_c_hosts_and_older_ones_get_the_default() {
    assert_eq!(WetHairSimDesc::default_values().water_adhesion_length, 0.0);
    let g = paper(16);
    let run = |length: f32, size: u32| -> Vec<f32> {
        let mut d = wet_desc(g);
        assert_eq!(d.water_adhesion_length, 0.02, "init's default");
        d.held_water.enabled = 0;
        d.water_adhesion_length = length;
        d.struct_size = size;
        let s = create(&d);
        // Above the head, among the roots: every strand has its root there.
        let pos: Vec<f32> = (0..8).flat_map(|k| [0.01 * k as f32 - 0.04, 0.0, 0.11]).collect();
        let r = unsafe { wethair_sim_add_water(s, pos.as_ptr(), std::ptr::null(), 8) };
        assert_eq!(r, WETHAIR_OK, "{}", last_error());
        stepped_vertices(s, 30)
    };
    let full = std::mem::size_of::<WetHairSimDesc>() as u32;
    let bits = |v: Vec<f32>| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let per_point = bits(run(0.0, full));
    assert_eq!(bits(run(f32::NAN, 344)), per_point, "a 0.7.0 host: per point");
    assert_ne!(
        bits(run(0.02, full)),
        per_point,
        "over 2 cm: the roots and tips pull half"
    );
    unsafe { wethair_groom_destroy(g) };
}

/// The live error estimate through C: -1 unless `error_estimate_stride` asks for it (and for
/// a 0.2.0 host, whose desc ends before the field), a positive figure in metres when it does.
#[test]
fn the_error_estimate_reaches_c_hosts() {
    let g = paper(16);
    for (stride, size, estimated) in [(0, 232, false), (4, 232, true), (4, 216, false)] {
        let mut d = wet_desc(g);
        d.held_water.enabled = 0;
        d.error_estimate_stride = stride;
        d.struct_size = size;
        let s = create(&d);
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
        let st = stats(s);
        if estimated {
            assert!(
                st.error_estimate > 0.0 && st.error_estimate_max >= st.error_estimate && st.error_estimate_max < 0.01,
                "stride {stride}: {} / {} m",
                st.error_estimate,
                st.error_estimate_max
            );
        } else {
            assert_eq!(
                (st.error_estimate, st.error_estimate_max),
                (-1.0, -1.0),
                "stride {stride}, size {size}"
            );
        }
        unsafe { wethair_sim_destroy(s) };
    }
    unsafe { wethair_groom_destroy(g) };
}

/// The error budget through C: a NaN or negative tolerance, or a cap below the substeps, is
/// refused by name; a tight budget raises `WetHairStats::substeps` above the desc's.
#[test]
fn the_error_budget_reaches_c_hosts() {
    let g = paper(16);
    for (tolerance, max_substeps, name) in [
        (f32::NAN, 64, "tolerance"),
        (-1.0, 64, "tolerance"),
        (1e-4, 2, "max_substeps"),
    ] {
        let mut d = wet_desc(g);
        d.tolerance = tolerance;
        d.max_substeps = max_substeps;
        let mut s = null_mut();
        assert_eq!(
            unsafe { wethair_sim_create(&d, &mut s) },
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert!(s.is_null() && last_error().contains(name), "{}", last_error());
    }
    let mut d = wet_desc(g);
    d.held_water.enabled = 0;
    d.integrator = wethair::Integrator::SYMPLECTIC_EULER as u32;
    d.substeps = 4;
    d.tolerance = 1e-5;
    let mut s = create(&d);
    assert_eq!(stats(s).substeps, 4);
    for _ in 0..30 {
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
    }
    let st = stats(s);
    assert!(
        st.substeps > 4 && st.error_estimate > 0.0,
        "substeps {}, estimate {}",
        st.substeps,
        st.error_estimate
    );
    // AUTO under the budget: at one substep symplectic Euler is unstable on the paper groom,
    // so it starts with BDF2, then moves to symplectic Euler, stable and far cheaper there.
    unsafe { wethair_sim_destroy(s) };
    d.integrator = wethair::Integrator::AUTO as u32;
    d.substeps = 1;
    d.tolerance = 1e-4;
    s = create(&d);
    assert_eq!(stats(s).integrator, wethair::Integrator::BDF2 as u32);
    let mut seen = vec![];
    for _ in 0..30 {
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
        let st = stats(s);
        seen.push((st.integrator, st.substeps));
    }
    assert_eq!(seen[0], (wethair::Integrator::BDF2 as u32, 1), "chose {seen:?}");
    assert_eq!(
        seen[29].0,
        wethair::Integrator::SYMPLECTIC_EULER as u32,
        "chose {seen:?}"
    );
    unsafe {
        wethair_sim_destroy(s);
        wethair_groom_destroy(g);
    }
}

/// Drops that meet coalesce, through C (since 0.9.0): two drops 0.05 mm apart in the hair
/// share one place after a step with `water_pile_cell` = 0.1 mm, on the CPU backend and on the
/// GPU's where an adapter exists (always under `WETHAIR_REQUIRE_GPU=1`); a 0.8.0 host (360
/// bytes) gets 0 whatever lies past its struct, and its drops keep apart.
#[test]
fn drops_that_meet_coalesce_through_c_and_older_hosts_keep_them_apart() {
    let g = paper(64);
    // The drops' places after a step, or None where the GPU cannot start and none is required.
    let places = |cell: f32, size: u32, backend: wethair::Backend| -> Option<Vec<[f32; 3]>> {
        let mut d = wet_desc(g);
        d.backend = backend as u32;
        d.held_water.enabled = 0; // the paper's model
        d.water_pile_cell = cell;
        d.struct_size = size;
        let mut s = null_mut();
        let r = unsafe { wethair_sim_create(&d, &mut s) };
        if r != WETHAIR_OK
            && backend == wethair::Backend::GPU
            && std::env::var("WETHAIR_REQUIRE_GPU").as_deref() != Ok("1")
        {
            eprintln!("no GPU adapter, GPU case not run: {}", last_error());
            return None;
        }
        assert_eq!(r, WETHAIR_OK, "{}", last_error());
        let (a, b) = ([0.0f32, 0.0, 0.125], [0.00005f32, 0.0, 0.125]);
        let pos = [a, b].concat();
        assert_eq!(
            unsafe { wethair_sim_add_water(s, pos.as_ptr(), std::ptr::null(), 2) },
            WETHAIR_OK
        );
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
        let (mut out, mut n) = ([0.0f32; 6], 0u32);
        assert_eq!(
            unsafe { wethair_sim_get_water(s, out.as_mut_ptr(), 2, &mut n) },
            WETHAIR_OK
        );
        unsafe { wethair_sim_destroy(s) };
        assert_eq!(n, 2, "both drops are still there");
        Some(vec![[out[0], out[1], out[2]], [out[3], out[4], out[5]]])
    };
    let size = std::mem::size_of::<WetHairSimDesc>() as u32;
    for backend in [wethair::Backend::CPU, wethair::Backend::GPU] {
        let Some(met) = places(1.0e-4, size, backend) else {
            continue;
        };
        assert_eq!(met[0], met[1], "{backend:?}: coalesced, one place");
        let apart = places(0.0, size, backend).unwrap();
        assert_ne!(apart[0], apart[1], "{backend:?}: off, they keep apart");
        let old = places(1.0e-4, 360, backend).unwrap();
        assert_ne!(old[0], old[1], "{backend:?}: a 0.8.0 host gets 0");
    }
    unsafe { wethair_groom_destroy(g) };
}
