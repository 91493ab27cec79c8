//! Physics tests: analytic cases and invariants on the CPU backend.

use glam::Vec3;
use wethair::groom::{paper_scene, Groom};
use wethair::physics::adhesion;
use wethair::scenes::{shower, Lcg};
use wethair::{SimParams, Simulation, SpringParams};

fn chain(points: usize, seg: f32, pinned_root: bool) -> Groom {
    let pos: Vec<Vec3> = (0..points).map(|i| Vec3::new(0.0, 0.0, -(i as f32) * seg)).collect();
    let mut pin = vec![false; points];
    pin[0] = pinned_root;
    Groom::new(pos, &[points as u32], Some(pin), None, 1e-3).unwrap()
}

/// A vertical chain under gravity settles where each spring carries the weight below it:
/// extension of spring j = (n - 1 - j) m g / k.
#[test]
fn hanging_chain_settles_at_static_stretch() {
    let (n, seg, m, k, g) = (6usize, 0.02f32, 1e-3f32, 40.0f32, 9.81f32);
    let params = SimParams {
        stretch: SpringParams {
            stiffness: k,
            damping: 0.02,
        },
        bend: SpringParams {
            stiffness: 0.0,
            damping: 0.0,
        },
        air_drag: 0.01,
        threads: 1,
        ..SimParams::paper()
    };
    let mut sim = Simulation::new(&chain(n, seg, true), params).unwrap();
    for _ in 0..600 {
        sim.step(1.0 / 60.0).unwrap();
    }
    let x = sim.positions();
    for j in 0..n - 1 {
        let ext = (x[j + 1] - x[j]).length() - seg;
        let expect = (n - 1 - j) as f32 * m * g / k;
        assert!(
            (ext - expect).abs() <= 0.01 * expect,
            "spring {j}: extension {ext} vs analytic {expect}"
        );
    }
}

/// One mass on one spring oscillates with period 2π√(m/k) (symplectic Euler at ωh = 0.21
/// shifts it by 0.2%; the test allows 1%). Released at rest length under gravity, it
/// oscillates about the equilibrium `mg/k` lower.
#[test]
fn one_spring_period_matches_analytic() {
    let (m, k, seg, g) = (1e-3f32, 10.0f32, 0.02f32, 9.81f32);
    let params = SimParams {
        stretch: SpringParams {
            stiffness: k,
            damping: 0.0,
        },
        bend: SpringParams {
            stiffness: 0.0,
            damping: 0.0,
        },
        substeps: 1,
        threads: 1,
        ..SimParams::paper()
    };
    let mut sim = Simulation::new(&chain(2, seg, true), params).unwrap();
    let h = 1.0 / 480.0;
    let z_eq = -(seg + m * g / k);
    let mut crossings = vec![];
    let mut prev = sim.positions()[1].z - z_eq;
    for step in 1..=2000 {
        sim.step(h).unwrap();
        let cur = sim.positions()[1].z - z_eq;
        if prev < 0.0 && cur >= 0.0 {
            crossings.push((step as f32 - 1.0 + prev / (prev - cur)) * h);
        }
        prev = cur;
    }
    assert!(crossings.len() >= 20, "only {} periods seen", crossings.len());
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f32;
    let analytic = std::f32::consts::TAU * (m / k).sqrt();
    assert!(
        (period / analytic - 1.0).abs() < 0.01,
        "period {period} vs analytic {analytic}"
    );
}

/// Without gravity a groom at rest stays put to 1e-6 m.
#[test]
fn strand_at_rest_stays_at_rest() {
    let groom = paper_scene(500, 6).unwrap();
    let params = SimParams {
        gravity: Vec3::ZERO,
        ..SimParams::paper()
    };
    let mut sim = Simulation::new(&groom, params).unwrap();
    let x0 = sim.positions();
    for _ in 0..100 {
        sim.step(1.0 / 60.0).unwrap();
    }
    let worst = x0
        .iter()
        .zip(sim.positions())
        .map(|(a, b)| (*a - b).length())
        .fold(0.0, f32::max);
    assert!(worst <= 1e-6, "moved {worst} m");
}

/// With damping, total energy (kinetic + springs + gravity) never rises above where it
/// started, and its maximum over successive quarter seconds never increases: the discrete
/// integrator's energy wobbles within a step (symplectic Euler conserves a nearby, not the
/// exact, energy), but damping drains it over time. Both damping models.
#[test]
fn damped_energy_never_increases() {
    for model in [wethair::DampingModel::AXIAL, wethair::DampingModel::RELATIVE] {
        let groom = paper_scene(200, 6).unwrap();
        let params = SimParams {
            damping_model: model,
            threads: 1,
            ..SimParams::paper()
        };
        let mut sim = Simulation::new(&groom, params).unwrap();
        let e0 = sim.energy().total();
        let tol = 1e-6 * e0.abs().max(1e-3);
        let mut window_max = vec![];
        for f in 0..600 {
            sim.step(1.0 / 60.0).unwrap();
            let e = sim.energy().total();
            assert!(e <= e0 + tol, "{model:?} frame {f}: energy {e} above the initial {e0}");
            if f % 15 == 0 {
                window_max.push(f64::NEG_INFINITY);
            }
            let w = window_max.last_mut().unwrap();
            *w = w.max(e);
        }
        for (i, pair) in window_max.windows(2).enumerate() {
            assert!(
                pair[1] <= pair[0] + tol,
                "{model:?}: window {} max {} above window {} max {}",
                i + 1,
                pair[1],
                i,
                pair[0]
            );
        }
        assert!(
            window_max.last().unwrap() < &(e0 - 1e-3 * e0.abs()),
            "{model:?}: damping removed no energy"
        );
    }
}

/// Adhesion is equal and opposite: with free-floating strands (nothing pinned), no drag and
/// no gravity, hair plus water keep zero total momentum while the water pulls the hair.
#[test]
fn adhesion_conserves_momentum() {
    let base = paper_scene(400, 6).unwrap();
    let groom = Groom::new(
        base.positions().to_vec(),
        &vec![6; 400],
        Some(vec![false; 2400]),
        None,
        1e-3,
    )
    .unwrap();
    let mut params = SimParams {
        gravity: Vec3::ZERO,
        ..SimParams::paper()
    };
    params.water.drag = 0.0;
    let mut sim = Simulation::new(&groom, params.clone()).unwrap();
    let water = wethair::scenes::on_hair(base.positions(), 200, &mut Lcg(7));
    sim.add_water(&water, &[]).unwrap();
    let mut moved = 0.0f64;
    for _ in 0..60 {
        sim.step(1.0 / 60.0).unwrap();
        let p = sim.momentum();
        let scale: f64 = sim.velocities().iter().map(|v| v.length() as f64 * 1e-3).sum::<f64>()
            + sim
                .water_velocities()
                .unwrap()
                .iter()
                .map(|v| v.length() as f64 * 1e-3)
                .sum::<f64>();
        moved = moved.max(scale);
        assert!(
            p.length() <= 1e-5 * scale.max(1e-9),
            "momentum {p:?} against scale {scale}"
        );
    }
    assert!(moved > 1e-4, "water did not move the hair (momentum scale {moved})");

    // With gravity, momentum grows exactly as total mass × g × t.
    params.gravity = Vec3::new(0.0, 0.0, -9.81);
    let mut sim = Simulation::new(&groom, params).unwrap();
    sim.add_water(&water, &[]).unwrap();
    for _ in 0..30 {
        sim.step(1.0 / 60.0).unwrap();
    }
    let mass = 2400.0 * 1e-3 + sim.water_positions().unwrap().len() as f64 * 1e-3;
    let expect = mass * -9.81 * 0.5;
    let p = sim.momentum();
    assert!(
        (p.z - expect).abs() <= 1e-4 * expect.abs(),
        "p_z {} vs M g t {expect}",
        p.z
    );
    assert!(p.x.abs() + p.y.abs() <= 1e-4 * expect.abs());
}

/// Eq. 2's profile: negative inside r_min, 0 at r_min, 1 halfway, 0 at r_max and beyond; the
/// force at d = 0 is zero (no direction), and points toward the particle in the shell.
#[test]
fn adhesion_profile_matches_eq2() {
    let (r0, r1) = (0.002f32, 0.008f32);
    let g0 = adhesion::profile(0.0, r0, r1);
    let expect0 = 1.0 - ((r0 + r1) / (r1 - r0)).powi(2);
    assert!((g0 - expect0).abs() < 1e-6 && g0 < 0.0);
    assert!(adhesion::profile(r0, r0, r1).abs() < 1e-6);
    assert!((adhesion::profile(0.5 * (r0 + r1), r0, r1) - 1.0).abs() < 1e-6);
    assert!(adhesion::profile(r1, r0, r1).abs() < 1e-6);
    assert_eq!(adhesion::profile(r1 * 1.01, r0, r1), 0.0);
    let s = 0.01;
    assert_eq!(adhesion::force_on_hair(Vec3::ZERO, Vec3::ZERO, r0, r1, s), Vec3::ZERO);
    let mid = adhesion::force_on_hair(Vec3::ZERO, Vec3::new(0.005, 0.0, 0.0), r0, r1, s);
    assert!((mid - Vec3::new(s, 0.0, 0.0)).length() < 1e-6, "{mid:?}");
    let inner = adhesion::force_on_hair(Vec3::ZERO, Vec3::new(0.001, 0.0, 0.0), r0, r1, s);
    assert!(
        inner.x < 0.0,
        "inside r_min the particle pushes the hair away: {inner:?}"
    );
    assert_eq!(
        adhesion::force_on_hair(Vec3::ZERO, Vec3::new(0.009, 0.0, 0.0), r0, r1, s),
        Vec3::ZERO
    );
}

/// Clumping happens: after a shower of 1,000 particles over the paper scene, the mean
/// tip-to-nearest-tip distance falls below 0.75 of the same scene dry.
#[test]
fn water_clumps_the_paper_scene() {
    let groom = paper_scene(10_000, 6).unwrap();
    let params = SimParams::paper_scene_with_head();
    let mut dry = Simulation::new(&groom, params.clone()).unwrap();
    let mut wet = Simulation::new(&groom, params).unwrap();
    let mut rng = Lcg(12345);
    for f in 0..200 {
        if f < 20 {
            let (p, v) = shower(50, &mut rng);
            wet.add_water(&p, &v).unwrap();
        }
        dry.step(1.0 / 60.0).unwrap();
        wet.step(1.0 / 60.0).unwrap();
    }
    let (d, w) = (dry.stats().clumping, wet.stats().clumping);
    assert!(w < 0.75 * d, "wet clumping {w} not below 0.75 x dry {d}");
    assert!(wet.stats().particles > 0, "all water ran off");
}

/// Hair does not pass through the head collider.
#[test]
fn head_collider_keeps_hair_outside() {
    let groom = paper_scene(2000, 6).unwrap();
    let mut sim = Simulation::new(&groom, SimParams::paper_scene_with_head()).unwrap();
    for _ in 0..120 {
        sim.step(1.0 / 60.0).unwrap();
    }
    let inner = sim.positions().iter().map(|p| p.length()).fold(f32::INFINITY, f32::min);
    assert!(inner >= 0.1 - 1e-5, "a point is {inner} m from the head centre");
    let mut free = Simulation::new(&groom, SimParams::paper()).unwrap();
    for _ in 0..120 {
        free.step(1.0 / 60.0).unwrap();
    }
    let inner = free
        .positions()
        .iter()
        .map(|p| p.length())
        .fold(f32::INFINITY, f32::min);
    assert!(
        inner < 0.09,
        "without the collider hair should swing through the head ({inner})"
    );
}

/// Roots follow the head transform exactly at the end of a step.
#[test]
fn roots_follow_the_head() {
    let groom = paper_scene(100, 6).unwrap();
    let mut sim = Simulation::new(&groom, SimParams::paper()).unwrap();
    let m = glam::Mat4::from_rotation_translation(glam::Quat::from_rotation_z(0.5), Vec3::new(0.1, -0.2, 0.05));
    sim.set_head_transform(m).unwrap();
    sim.step(1.0 / 60.0).unwrap();
    let x = sim.positions();
    for s in 0..100 {
        let want = m.transform_point3(groom.positions()[s * 6]);
        assert!((x[s * 6] - want).length() < 1e-6);
    }
}

/// A capsule collider (a limb, a shoulder) keeps hair outside too, and follows the head.
#[test]
fn capsule_collider_keeps_hair_outside() {
    let groom = paper_scene(2000, 6).unwrap();
    let (a, b, r) = (Vec3::new(-0.2, 0.0, -0.05), Vec3::new(0.2, 0.0, -0.05), 0.12);
    let params = SimParams {
        colliders: vec![wethair::Shape::Capsule { a, b, radius: r }],
        ..SimParams::paper()
    };
    let mut sim = Simulation::new(&groom, params).unwrap();
    let head = glam::Mat4::from_translation(Vec3::new(0.0, 0.0, 0.03));
    sim.set_head_transform(head).unwrap();
    for _ in 0..120 {
        sim.step(1.0 / 60.0).unwrap();
    }
    let (a, b) = (head.transform_point3(a), head.transform_point3(b));
    let pinned = groom.pinned();
    for (i, p) in sim.positions().iter().enumerate() {
        let t = ((*p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
        let d = (*p - (a + (b - a) * t)).length();
        assert!(
            pinned[i] || d >= r - 1e-5,
            "point {i} is {d} m from the capsule axis (radius {r})"
        );
    }
}

/// The row form of eq. 2 (one particle against 8 hair points) equals the per-point form; in a
/// guide groom each lane's reaction is its bundle's (its pull on the particle times the
/// strands it stands for) while the pull on the lane stays its own.
#[allow(clippy::needless_range_loop)]
#[test]
fn adhesion_row_and_point_forms_agree() {
    use wethair::physics::lanes::{L3, W};
    let mut rng = Lcg(3);
    let (r0, r1, s) = (0.002f32, 0.008f32, 0.01f32);
    let mut x = L3::ZERO;
    for l in 0..W {
        x.set(l, Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.01);
    }
    let n = 40;
    let q: Vec<[f32; 3]> = (0..n)
        .map(|_| [rng.next_f32() * 0.012, rng.next_f32() * 0.012, rng.next_f32() * 0.012])
        .collect();
    let cols: Vec<Vec<f32>> = (0..3).map(|c| q.iter().map(|p| p[c]).collect()).collect();
    let run = adhesion::Run {
        x: &cols[0],
        y: &cols[1],
        z: &cols[2],
    };
    let bundles: [f32; W] = [1.0, 10.0, 2.5, 1.0, 40.0, 3.0, 1.0, 7.0];
    for bundle in [None, Some(&bundles)] {
        let (mut fx, mut fy, mut fz) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let (mut acc, mut near, mut reactions) = (L3::ZERO, [0.0; W], Vec::new());
        adhesion::gather_run_lanes(
            &x,
            &[1.0; W],
            &[1.0; W],
            bundle,
            run,
            0,
            &mut reactions,
            &mut acc,
            &mut near,
            r0,
            r1,
            adhesion::Strength::uniform(s),
            None,
        );
        for r in &reactions {
            let j = r.slot as usize;
            fx[j] += r.f[0];
            fy[j] += r.f[1];
            fz[j] += r.f[2];
        }
        // The per-point form: the scalar law, pair by pair.
        let (mut gx, mut gy, mut gz) = (vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n]);
        for l in 0..W {
            let k = bundle.map_or(1.0, |b| b[l]);
            let (mut f, mut any) = (Vec3::ZERO, false);
            for (j, p) in q.iter().enumerate() {
                let (h, w) = (x.get(l), Vec3::from(*p));
                let fj = adhesion::force_on_hair(h, w, r0, r1, s);
                f += fj;
                gx[j] -= fj.x * k;
                gy[j] -= fj.y * k;
                gz[j] -= fj.z * k;
                any |= (w - h).length_squared() <= r1 * r1;
            }
            assert!(
                (f - acc.get(l)).length() <= 1e-6 * (1.0 + f.length()),
                "lane {l}: {f:?} vs {:?}",
                acc.get(l)
            );
            assert_eq!(any, near[l] > 0.0);
        }
        for j in 0..n {
            let (a, b) = (Vec3::new(fx[j], fy[j], fz[j]), Vec3::new(gx[j], gy[j], gz[j]));
            assert!(
                (a - b).length() <= 1e-6 * (1.0 + b.length()),
                "{bundle:?}: particle {j}: {a:?} vs {b:?}"
            );
        }
        assert!(
            near.iter().any(|&v| v > 0.0),
            "the test cloud should put particles within r_max"
        );
    }
}

/// The air drag's law (`physics/per_length.rs`): quoted over a length `L`, a strand's points' drag
/// coefficients sum to `c` times its length over `L` however its segments are cut, its ends
/// taking half a segment's; with `L` = 0 every point takes `c` as given.
#[test]
fn air_drag_per_length_sums_to_the_strand_and_per_point_stays_as_given() {
    use wethair::physics::per_length::PerLength;
    let c = 3.0e-3f32;
    let per_length = PerLength::new(c, 0.02);
    for segments in [vec![0.02f32; 5], vec![0.005, 0.03, 0.01, 0.04, 0.015]] {
        let total: f32 = segments.iter().sum();
        let at = |i: usize| {
            let before = if i > 0 { segments[i - 1] } else { 0.0 };
            per_length.at(before, segments.get(i).copied().unwrap_or(0.0))
        };
        let sum: f32 = (0..=segments.len()).map(at).sum();
        assert!(
            (sum - c * total / 0.02).abs() < 1e-6 * c,
            "{segments:?}: {sum} against {}",
            c * total / 0.02
        );
        assert!(
            (at(0) - c * segments[0] / 0.04).abs() < 1e-9,
            "the root takes half its segment"
        );
    }
    let per_point = PerLength::new(c, 0.0);
    assert!(!per_point.per_length() && per_length.per_length());
    assert_eq!(per_point.at(0.005, 0.04), c);
    assert_eq!(per_point.at(0.0, 0.0), c);
    assert!(PerLength::new(0.0, 0.02).is_zero() && PerLength::new(0.0, 0.0).is_zero());
}
