//! Resolution-independent material parameters (issue 13, item 10): springs follow from EA and
//! EI and their rest lengths, so a strand sags the same however finely it is sampled; the
//! default parameters keep every shipped groom within 2% of its rest length; degenerate
//! segments are welded at load and counted; the paper's springs map exactly. Held water runs
//! down a strand at the same speed, and a drop soaks into it at the same rate, however finely
//! it is sampled.

use glam::Vec3;
use wethair::groom::{load_file_with, Groom, LoadOptions, UpAxis};
use wethair::params::{MaterialParams, SpringModel};
use wethair::{Backend, HeldWater, SimParams, Simulation};

use crate::common::{backends, serial};

fn data(name: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// A straight strand of `length` m hanging from a pinned root at the origin, sampled at `n`
/// points, 1 g per metre (masses from the linear density, as the loaders give them).
fn hanging_strand(length: f32, n: u32) -> Groom {
    let line = Groom::new(vec![Vec3::ZERO, Vec3::new(0.0, 0.0, -length)], &[2], None, None, 1.0).unwrap();
    LoadOptions {
        resample_points: n,
        linear_density: 1e-3,
        weld_length: 0.0,
        ..Default::default()
    }
    .apply(&line)
    .unwrap()
}

/// How far the tip ends below its rest position after `seconds` under gravity.
fn sag(groom: &Groom, params: SimParams, seconds: f32) -> f32 {
    let rest = groom.positions()[groom.point_count() - 1];
    let mut sim = Simulation::new(groom, params).unwrap();
    for _ in 0..(seconds * 60.0) as usize {
        sim.step(1.0 / 60.0).unwrap();
    }
    rest.z - sim.positions()[groom.point_count() - 1].z
}

/// A simulation of `hanging_strand(length, n)` with every point pinned and one particle at
/// rest `y0` m beside its middle.
fn beside_pinned_strand(length: f32, n: u32, y0: f32, params: SimParams) -> Simulation {
    let line = hanging_strand(length, n);
    let pinned = vec![true; line.point_count()];
    let masses = Some(line.masses().to_vec());
    let groom = Groom::new(line.positions().to_vec(), &[n], Some(pinned), masses, 1.0).unwrap();
    let mut sim = Simulation::new(&groom, params).unwrap();
    sim.add_water(&[Vec3::new(y0, 0.0, -length / 2.0)], &[Vec3::ZERO])
        .unwrap();
    sim
}

/// `∫ f(d) dz` along a line `y0` m from a particle, over the stretch within `r_max` of it (`d`
/// the distance to the particle), by the midpoint rule at 1 µm.
fn along_reach(y0: f64, r_max: f64, f: impl Fn(f64) -> f64) -> f64 {
    let reach = (r_max * r_max - y0 * y0).sqrt();
    let ds = 1.0e-6;
    (0..(2.0 * reach / ds) as usize)
        .map(|k| {
            let z = -reach + (k as f64 + 0.5) * ds;
            f((y0 * y0 + z * z).sqrt()) * ds
        })
        .sum()
}

/// One strand sampled at 6, 16, 32 and 64 points sags by the same amount within 5% with the
/// default (material) parameters, on every backend; the amount is the continuum value
/// `ρ g L² / (2 EA)` within 5% (the bend springs, which also carry tension, add
/// `EI / (2 l² EA)` to the axial stiffness: under 2% here). The paper's per-spring model, for
/// contrast, sags over 3x more at 64 points than at 6.
#[test]
fn a_strand_sags_the_same_at_any_sampling() {
    let _g = serial();
    let length = 0.4f32;
    let m = MaterialParams::HAIR;
    let continuum = 1e-3 * 9.81 * length * length / (2.0 * m.stretch_modulus);
    for backend in backends() {
        let params = SimParams {
            backend,
            ..SimParams::default()
        };
        let sags: Vec<f32> = [6, 16, 32, 64]
            .iter()
            .map(|&n| sag(&hanging_strand(length, n), params.clone(), 3.0))
            .collect();
        println!("{backend:?}: sag at 6, 16, 32, 64 points {sags:?} m; continuum {continuum} m");
        for (&n, &s) in [6, 16, 32, 64].iter().zip(&sags) {
            assert!(
                (s / sags[3] - 1.0).abs() < 0.05,
                "{backend:?}: {n} points sag {s} m, 64 points {} m (all: {sags:?})",
                sags[3]
            );
            assert!(
                (s / continuum - 1.0).abs() < 0.05,
                "{backend:?}: {n} points sag {s} m, continuum {continuum} m"
            );
        }
    }
    // Per spring (the paper's model, its k for every spring): the finer, the softer.
    let per_spring = SimParams {
        backend: Backend::CPU,
        integrator: wethair::Integrator::IMPLICIT_EULER,
        ..SimParams::paper()
    };
    let coarse = sag(&hanging_strand(length, 6), per_spring.clone(), 3.0);
    let fine = sag(&hanging_strand(length, 64), per_spring, 3.0);
    println!("per spring: sag {coarse} m at 6 points, {fine} m at 64");
    assert!(
        fine > 3.0 * coarse,
        "per-spring sag {coarse} m at 6 points, {fine} m at 64"
    );
}

/// docs/WET_MODEL.md §6: water above the hold limit runs down a strand at `flow_speed` (0.1
/// m/s by default) however finely the strand is sampled. A hanging strand 0.3 m long, soaked
/// to twice its hold limits with no drying, sheds its excess from the tip as it arrives: the
/// tip's own half segment at once, then an even column moving at `v`, so `l / 2L + v t / L`
/// of it at `t` (`l` a segment). At 16, 31 and 61 points, on every backend, the shed part is
/// that within 0.04 at 1 s and 0.02 at 2 s. (With the mobility per segment, as before 0.7.0,
/// 61 points had shed 0.18 at 2 s and 16 points 0.68.)
#[test]
fn held_water_runs_down_a_strand_at_the_same_speed_at_any_sampling() {
    let _g = serial();
    let length = 0.3f32;
    let hw = HeldWater {
        dry_time: 0.0,
        ..HeldWater::ON
    };
    let speed = hw.flow_speed();
    assert!((speed - 0.1).abs() < 1e-6, "the default speed is 0.1 m/s, got {speed}");
    for backend in backends() {
        let mut params = SimParams {
            backend,
            held_water: hw,
            ..SimParams::default()
        };
        params.water.domain_radius = 100.0; // the drops stay counted as they fall
        for n in [16, 31, 61] {
            let mut sim = Simulation::new(&hanging_strand(length, n), params.clone()).unwrap();
            sim.soak(2.0).unwrap();
            let excess = sim.water_ledger().unwrap().held as f64 / 2.0;
            let mut shed = Vec::new();
            for f in 1..=120 {
                sim.step(1.0 / 60.0).unwrap();
                if f % 60 == 0 {
                    let l = sim.water_ledger().unwrap();
                    assert!(l.balanced(), "{l:?}");
                    shed.push((l.added - l.held) as f64 / excess);
                }
            }
            println!("{backend:?}, {n} points: shed {shed:?} of the excess at 1 and 2 s");
            for (k, (&got, tol)) in shed.iter().zip([0.04, 0.02]).enumerate() {
                let t = (k + 1) as f64;
                let tip = 0.5 / (n - 1) as f64;
                let want = tip + speed as f64 * t / length as f64;
                assert!(
                    (got - want).abs() < tol,
                    "{backend:?}, {n} points: shed {got} at {t} s, a column at {speed} m/s {want}"
                );
            }
        }
    }
}

/// docs/WET_MODEL.md §2: a drop soaks into hair at a rate set by the length of hair in its
/// reach, however finely that hair is sampled. A 1 mg drop rests 3 mm beside the middle of a
/// straight 6 cm strand (1 g/m, every point pinned, a pull too weak to move the drop); over
/// 0.1 s it empties as `e^(-K t)`, `K = (k_abs / ABSORB_LENGTH) ∫ ω ds` along the strand (ω
/// the distance weight), to the hair's slight filling. At 13, 25 and 49 points (5, 2.5 and
/// 1.25 mm apart), on every backend, the drop keeps that fraction within 0.03. (With the rate
/// per point, as before, the three kept 0.047, 0.003 and 0: a finer groom soaked a drop
/// faster.) The 1 mg drop's drag rate, 2000 /s, needs the particles' implicit drag.
#[test]
fn a_drop_soaks_into_hair_at_the_same_rate_at_any_sampling() {
    let _g = serial();
    let length = 0.06f32;
    let hw = HeldWater {
        dry_time: 0.0,
        ..HeldWater::ON
    };
    let (y0, seconds) = (0.003f64, 0.1f64);
    for backend in backends() {
        let mut params = SimParams {
            backend,
            held_water: hw,
            gravity: Vec3::ZERO,
            integrator: wethair::Integrator::SYMPLECTIC_EULER,
            ..SimParams::default()
        };
        params.water.particle_mass = 1.0e-6;
        params.water.adhesion = 1.0e-9;
        let w = &params.water;
        let (r_min, r_max) = (w.r_min as f64, w.r_max as f64);
        // ∫ ω ds over the strand beside the drop.
        let integral = along_reach(y0, r_max, |d| ((r_max - d) / (r_max - r_min)).clamp(0.0, 1.0));
        let k = hw.absorb_rate as f64 / wethair::physics::wet::ABSORB_LENGTH as f64 * integral;
        let want = (-k * seconds).exp();
        let mut kept = Vec::new();
        for n in [13, 25, 49] {
            let mut sim = beside_pinned_strand(length, n, y0 as f32, params.clone());
            let full = sim.water_ledger().unwrap().in_particles as f64;
            for _ in 0..(seconds * 60.0).round() as usize {
                sim.step(1.0 / 60.0).unwrap();
            }
            let l = sim.water_ledger().unwrap();
            assert!(l.balanced(), "{l:?}");
            kept.push(l.in_particles as f64 / full);
        }
        println!("{backend:?}: the drop keeps {kept:?} at 13, 25, 49 points after {seconds} s; e^(-K t) {want}");
        for (n, got) in [13, 25, 49].iter().zip(&kept) {
            assert!(
                (got - want).abs() < 0.03,
                "{backend:?}, {n} points: the drop keeps {got}, e^(-K t) = {want} (all: {kept:?})"
            );
        }
    }
}

/// A steady wind blows a strand to the same angle however finely it is sampled (METHOD.md §2,
/// "Air drag"). With the drag quoted over `air_drag_length` of hair, each point feels
/// `c ℓ_i / L` sideways and `ρ ℓ_i g` down (masses from the linear density), the same ratio at
/// every free point, tip included: a hanging strand settles straight at
/// `atan(c W / (L ρ g))` from the vertical. 0.3 m of 1 g/m hair at 7, 13 and 25 points, the
/// default parameters (implicit Euler, which takes the drag in its solve), on every backend:
/// within 0.05° of it (measured: 45.544-45.547° against 45.550°). With the drag on every point
/// (`air_drag_length` 0), the same `c` blows the 7-point strand to 28° and the 25-point one to
/// 61°.
#[test]
fn a_wind_blows_a_strand_to_the_same_angle_at_any_sampling() {
    let _g = serial();
    let (length, c, w) = (0.3f32, 2.0e-4f32, 1.0f32);
    let angle_of = |n: u32, params: &SimParams| -> f64 {
        let groom = hanging_strand(length, n);
        let mut sim = Simulation::new(&groom, params.clone()).unwrap();
        for _ in 0..120 {
            sim.step(1.0 / 60.0).unwrap();
        }
        let x = sim.positions();
        let d = x[n as usize - 1] - x[0];
        (d.x as f64).atan2(-d.z as f64).to_degrees()
    };
    for backend in backends() {
        let mut params = SimParams {
            backend,
            air_drag: c,
            ..SimParams::default()
        };
        params.wind.velocity = Vec3::new(w, 0.0, 0.0);
        let l = params.air_drag_length as f64;
        let want = ((c * w) as f64 / (l * 1e-3 * 9.81)).atan().to_degrees();
        let angles: Vec<f64> = [7, 13, 25].iter().map(|&n| angle_of(n, &params)).collect();
        println!("{backend:?}: the wind blows 7, 13, 25 points to {angles:?} deg; atan(c W / (L rho g)) = {want} deg");
        for (n, got) in [7, 13, 25].iter().zip(&angles) {
            assert!(
                (got - want).abs() < 0.05,
                "{backend:?}, {n} points: {got} deg against {want} (all: {angles:?})"
            );
        }
    }
    // Per point, as before 0.8.0: the finer the strand, the harder it is blown.
    let mut per_point = SimParams {
        backend: Backend::CPU,
        air_drag: c,
        air_drag_length: 0.0,
        ..SimParams::default()
    };
    per_point.wind.velocity = Vec3::new(w, 0.0, 0.0);
    let (coarse, fine) = (angle_of(7, &per_point), angle_of(25, &per_point));
    println!("per point: {coarse} deg at 7 points, {fine} deg at 25");
    assert!(
        fine > coarse + 20.0,
        "per point: {coarse} deg at 7 points, {fine} at 25"
    );
}

/// A drop pulls a strand alike however finely it is sampled (METHOD.md §1): eq. 2 quoted over
/// `water.adhesion_length` of hair gives point `i` the pull `s ℓ_i / L g(d)`, so the strand's
/// pull on the drop is a Riemann sum of `(s / L) ∫ g(d) y0 / d dz` along it. A heavy drop 3 mm
/// beside a pinned 6 cm strand, held still by its mass for one step without gravity: its
/// velocity after the step is `dt` times that over its mass, within 4 % at 13, 25 and 49
/// points on every backend (measured +3.1 %, -2.8 %, -0.6 %: the sum's own error, 5 mm
/// samples across a pull 15 mm wide). With the pull per point, it doubled with each halving of
/// the segments.
#[test]
fn a_drop_pulls_a_strand_alike_at_any_sampling() {
    let _g = serial();
    let length = 0.06f32;
    let (y0, dt) = (0.003f64, 1.0f64 / 60.0);
    for backend in backends() {
        let mut params = SimParams {
            backend,
            gravity: Vec3::ZERO,
            integrator: wethair::Integrator::SYMPLECTIC_EULER,
            ..SimParams::default()
        };
        params.water.particle_mass = 0.1;
        params.water.drag = 0.0;
        let w = &params.water;
        let (r_min, r_max, s) = (w.r_min as f64, w.r_max as f64, w.adhesion as f64);
        // ∫ g(d) y0 / d dz over the strand beside the drop.
        let integral = along_reach(y0, r_max, |d| {
            let u = (2.0 * d - r_min - r_max) / (r_min - r_max);
            (1.0 - u * u) * y0 / d
        });
        let want = s / w.adhesion_length as f64 * integral / w.particle_mass as f64 * dt;
        let mut got = Vec::new();
        for n in [13, 25, 49] {
            let mut sim = beside_pinned_strand(length, n, y0 as f32, params.clone());
            sim.step(dt as f32).unwrap();
            let (_, vel) = sim.water().unwrap();
            got.push(-vel[0].x as f64);
        }
        println!("{backend:?}: the drop's speed toward the strand after a step at 13, 25, 49 points {got:?} m/s; (s / L) integral dt / m {want}");
        for (n, v) in [13, 25, 49].iter().zip(&got) {
            assert!(
                (v / want - 1.0).abs() < 0.04,
                "{backend:?}, {n} points: {v} m/s against {want} (all: {got:?})"
            );
        }
    }
}

/// The shipped grooms, loaded with the default options (only their units and axes given)
/// and simulated with the default parameters for 2 s under gravity from their rest pose: no
/// segment is ever more than 2% longer than at rest.
#[test]
fn shipped_grooms_stretch_under_two_percent_with_defaults() {
    let _g = serial();
    for (name, scale, up) in [
        ("Ratboy_mohawk.tfx", 1.0, UpAxis::KEEP),
        ("ponytail_back.tfx", 0.01, UpAxis::Y_TO_Z),
        ("ponytail_front_top.tfx", 0.01, UpAxis::Y_TO_Z),
    ] {
        let opt = LoadOptions {
            scale,
            up_axis: up,
            ..Default::default()
        };
        let groom = load_file_with(&data(name), &opt).unwrap();
        let params = SimParams {
            backend: Backend::CPU,
            ..SimParams::default()
        };
        let mut sim = Simulation::new(&groom, params).unwrap();
        let rest = groom.positions().to_vec();
        let mut worst = 0.0f32;
        for _ in 0..120 {
            sim.step(1.0 / 60.0).unwrap();
            let x = sim.positions();
            for s in 0..groom.strand_count() {
                for i in groom.strand_range(s).start..groom.strand_range(s).end - 1 {
                    let l0 = (rest[i + 1] - rest[i]).length();
                    worst = worst.max((x[i + 1] - x[i]).length() / l0 - 1.0);
                }
            }
        }
        println!("{name}: largest stretch {:.3}%", 100.0 * worst);
        assert!(worst < 0.02, "{name}: a segment stretched {:.2}%", 100.0 * worst);
    }
}

/// Segments shorter than the weld length are welded at load and counted in the report's
/// message; the mohawk has 124 under 10 µm and more under 0.1 mm. With welding off every
/// point is kept.
#[test]
fn degenerate_segments_are_welded_and_counted() {
    let keep = LoadOptions {
        weld_length: 0.0,
        ..Default::default()
    };
    let all = load_file_with(&data("Ratboy_mohawk.tfx"), &keep).unwrap();
    assert_eq!(all.point_count(), 2228 * 32);
    assert_eq!(all.load_report().message(), "");
    let welded = load_file_with(&data("Ratboy_mohawk.tfx"), &LoadOptions::default()).unwrap();
    let r = *welded.load_report();
    assert!(r.welded_points >= 124, "{r:?}");
    assert_eq!(
        welded.point_count() + r.welded_points as usize,
        all.point_count(),
        "every point is kept or counted"
    );
    assert_eq!(welded.strand_count() + r.dropped_strands as usize, 2228);
    let msg = r.message();
    assert!(
        msg.contains(&format!("welded {} points", r.welded_points)) && msg.contains("0.0001 m"),
        "{msg}"
    );
    // No segment left is shorter than the weld length.
    for s in 0..welded.strand_count() {
        let p = &welded.positions()[welded.strand_range(s)];
        assert!(p.windows(2).all(|w| (w[1] - w[0]).length() >= 1e-4), "strand {s}");
    }
    // A strand shorter than the weld length is dropped; a groom of only such strands is an
    // error naming the option.
    let tiny = Groom::new(vec![Vec3::ZERO, Vec3::new(0.0, 0.0, 1e-5)], &[2], None, None, 1e-3).unwrap();
    let e = LoadOptions::default().apply(&tiny).unwrap_err().to_string();
    assert!(e.contains("weld_length"), "{e}");
}

/// The paper scene's springs map exactly onto material properties (EA = 40 N/m x 0.02 m,
/// EI = 10 N/m x (0.04 m)^3): the material model gives every spring 40 and 10 N/m to f32
/// rounding, and 10 frames of the paper scene agree with the per-spring run within 1e-6 m
/// (later the headless paper scene amplifies such ulp-sized differences, about 3x every 5
/// frames, as any perturbation of it).
#[test]
fn the_paper_scene_maps_exactly_onto_material_properties() {
    let _g = serial();
    let groom = wethair::groom::paper_scene(200, 6).unwrap();
    let per_spring = SimParams {
        backend: Backend::CPU,
        ..SimParams::paper()
    };
    let material = SimParams {
        spring_model: SpringModel::MATERIAL,
        material: MaterialParams::PAPER,
        ..per_spring.clone()
    };
    let springs = wethair::plan::point_springs(&groom, &material);
    for s in &springs[..5] {
        assert!((s.stretch.stiffness / 40.0 - 1.0).abs() < 1e-5, "{s:?}");
        assert!((s.stretch.damping / 0.02 - 1.0).abs() < 1e-5, "{s:?}");
    }
    for s in &springs[..4] {
        assert!((s.bend.stiffness / 10.0 - 1.0).abs() < 1e-4, "{s:?}");
        assert!((s.bend.damping / 0.005 - 1.0).abs() < 1e-4, "{s:?}");
    }
    let mut a = Simulation::new(&groom, per_spring).unwrap();
    let mut b = Simulation::new(&groom, material).unwrap();
    for _ in 0..10 {
        a.step(1.0 / 60.0).unwrap();
        b.step(1.0 / 60.0).unwrap();
    }
    let d = a
        .positions()
        .iter()
        .zip(b.positions())
        .map(|(p, q)| (*p - q).length())
        .fold(0.0f32, f32::max);
    assert!(d < 1e-6, "paper per spring vs material: {d} m apart");
}

/// A host's own arrays are not welded; a near-zero segment gets the stiffness of a
/// `MIN_MATERIAL_LENGTH` one instead of an infinite one, and the default parameters run it.
#[test]
fn a_zero_length_segment_from_a_host_stays_finite() {
    let _g = serial();
    let pos = vec![
        Vec3::ZERO,
        Vec3::new(0.01, 0.0, 0.0),
        Vec3::new(0.01, 0.0, 0.0),
        Vec3::new(0.02, 0.0, 0.0),
    ];
    let groom = Groom::new(pos, &[4], None, None, 1e-5).unwrap();
    let springs = wethair::plan::point_springs(&groom, &SimParams::default());
    assert!(springs
        .iter()
        .all(|s| s.stretch.stiffness.is_finite() && s.bend.stiffness.is_finite()));
    assert_eq!(
        springs[1].stretch.stiffness,
        MaterialParams::HAIR.stretch_modulus / 1e-4
    );
    let mut sim = Simulation::new(
        &groom,
        SimParams {
            backend: Backend::CPU,
            ..SimParams::default()
        },
    )
    .unwrap();
    for _ in 0..60 {
        sim.step(1.0 / 60.0).unwrap();
    }
    assert!(sim.positions().iter().all(|p| p.is_finite()));
}

/// Through C: `wethair_sim_desc_init` with the current size gives the material model and AUTO;
/// with the 0.1.0 size (128) it gives the paper's per-spring defaults, and a simulation made
/// from it is bit-identical to `SimParams::paper()`; other sizes and NULL are refused with
/// nothing written. A desc of the 0.1.0 size never reads the new fields (they take the
/// per-spring default that 0.1.0 hosts meant). The load message reaches C.
#[test]
fn sim_desc_init_through_c() {
    use std::ptr::null_mut;
    use wethair::ffi::WetHairResult::*;
    use wethair::ffi::*;
    let _g = serial();
    let full = std::mem::size_of::<WetHairSimDesc>() as u32;
    // Fields added since 0.1.0 lie past its 128 bytes (its padding included).
    assert!(std::mem::offset_of!(WetHairSimDesc, spring_model) >= 128);
    unsafe {
        let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed().assume_init();
        assert_eq!(wethair_sim_desc_init(&mut d, full), WETHAIR_OK);
        assert_eq!(d.struct_size, full);
        assert_eq!(d.spring_model, SpringModel::MATERIAL as u32);
        assert_eq!(d.integrator, wethair::Integrator::AUTO as u32);
        assert_eq!(d.material.bend_modulus, MaterialParams::HAIR.bend_modulus);

        let mut old = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed().assume_init();
        old.spring_model = 0xdead;
        assert_eq!(wethair_sim_desc_init(&mut old, 128), WETHAIR_OK);
        assert_eq!(old.struct_size, 128);
        assert_eq!(old.integrator, wethair::Integrator::SYMPLECTIC_EULER as u32);
        assert_eq!((old.stretch.stiffness, old.bend.stiffness), (40.0, 10.0));
        assert_eq!(old.spring_model, 0xdead, "bytes past the host's size are not written");

        // A 0.1.0-sized desc ignores the garbage past its size and runs the paper exactly.
        let groom = wethair::groom::paper_scene(64, 6).unwrap();
        let mut gd = std::mem::MaybeUninit::<WetHairGroomDesc>::zeroed().assume_init();
        wethair_groom_desc_default(&mut gd);
        let counts = vec![6u32; 64];
        let xyz: Vec<f32> = groom.positions().iter().flat_map(|p| p.to_array()).collect();
        gd.strand_count = 64;
        gd.strand_point_counts = counts.as_ptr();
        gd.positions = xyz.as_ptr();
        gd.point_count = 64 * 6;
        let mut g = null_mut();
        assert_eq!(wethair_groom_create(&gd, &mut g), WETHAIR_OK);
        old.groom = g;
        old.backend = Backend::CPU as u32;
        let mut sim = null_mut();
        assert_eq!(wethair_sim_create(&old, &mut sim), WETHAIR_OK);
        let mut rust = Simulation::new(
            &groom,
            SimParams {
                backend: Backend::CPU,
                ..SimParams::paper()
            },
        )
        .unwrap();
        for _ in 0..20 {
            assert_eq!(wethair_sim_step(sim, 1.0 / 60.0), WETHAIR_OK);
            rust.step(1.0 / 60.0).unwrap();
        }
        let mut v = vec![0.0f32; 64 * 6 * 7];
        let mut written = 0usize;
        assert_eq!(
            wethair_sim_get_vertex_buffer(sim, v.as_mut_ptr(), v.len(), &mut written),
            WETHAIR_OK
        );
        let x = rust.positions();
        for (i, p) in x.iter().enumerate() {
            assert_eq!(&v[i * 7..i * 7 + 3], &p.to_array(), "point {i}");
        }
        wethair_sim_destroy(sim);
        wethair_groom_destroy(g);

        let before = d;
        for bad in [0u32, 4, 127, full + 8] {
            assert_eq!(wethair_sim_desc_init(&mut d, bad), WETHAIR_ERROR_STRUCT_SIZE, "{bad}");
        }
        assert_eq!(format!("{before:?}"), format!("{d:?}"), "nothing written on failure");
        assert_eq!(
            wethair_sim_desc_init(std::ptr::null_mut(), full),
            WETHAIR_ERROR_NULL_POINTER
        );
        // A bad spring model is refused naming the field.
        d.spring_model = 9;
        d.groom = null_mut::<WetHairGroom>();
        let mut s = null_mut();
        let mut load = std::mem::MaybeUninit::<WetHairLoadDesc>::zeroed().assume_init();
        wethair_load_desc_default(&mut load);
        let path = std::ffi::CString::new(data("Ratboy_mohawk.tfx").to_str().unwrap()).unwrap();
        let mut mohawk = null_mut();
        assert_eq!(
            wethair_groom_load_with_desc(path.as_ptr(), &load, &mut mohawk),
            WETHAIR_OK
        );
        let msg = std::ffi::CStr::from_ptr(wethair_groom_get_load_message(mohawk))
            .to_str()
            .unwrap();
        assert!(msg.starts_with("welded "), "{msg}");
        assert!(wethair_groom_get_load_message(std::ptr::null()).is_null());
        d.groom = mohawk;
        assert_eq!(wethair_sim_create(&d, &mut s), WETHAIR_ERROR_INVALID_ARGUMENT);
        let e = std::ffi::CStr::from_ptr(wethair_last_error_message()).to_str().unwrap();
        assert!(e.contains("spring_model"), "{e}");
        assert!(s.is_null());
        wethair_groom_destroy(mohawk);
    }
}
