//! The wet model's laws (docs/WET_MODEL.md, `physics::wet`), each against its analytic outcome:
//! exact drying independent of the step, a particle never gives more than it has, flow that
//! conserves water and drains a hanging strand to its tip, drips only above capacity, capacity
//! independent of sampling, absorption shares that follow the hair's length, the limpness
//! curve, bridge forces and deterministic gusts.

use glam::Vec3;
use wethair::physics::wet::*;

/// The default flow speed, m/s: `FLOW_MOBILITY` over `FLOW_LENGTH` of hair.
const SPEED: f32 = FLOW_MOBILITY * FLOW_LENGTH;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-30)
}

#[test]
fn drying_follows_the_exponential_law_whatever_the_step() {
    let k = evaporation_rate(0.0, 10.0, DRY_AIR_SPEED);
    assert_eq!(k, 0.1, "still air dries at 1/tau");
    assert!(
        evaporation_rate(4.0, 10.0, 1.0) > 2.9 * k,
        "moving air dries faster: 1 + sqrt(4)"
    );
    let m0 = to_quanta(1.0e-5);
    // 600 steps of 1/60 s, and 10 steps of 1 s, against m0 e^(-k t) after 10 s.
    let (mut fine, mut coarse, mut gone) = (m0, m0, 0u64);
    for _ in 0..600 {
        let e = evaporate(fine, k, 1.0 / 60.0);
        fine -= e;
        gone += e as u64;
    }
    for _ in 0..10 {
        coarse -= evaporate(coarse, k, 1.0);
    }
    let exact = m0 as f64 * (-1.0f64).exp();
    // Each step rounds to a whole quantum: at most 0.5 per step from the exact law.
    assert!((fine as f64 - exact).abs() <= 300.0, "{fine} vs {exact}");
    assert!((coarse as f64 - exact).abs() <= 5.0, "{coarse} vs {exact}");
    assert!(rel(fine as f64, exact) < 1e-4);
    assert_eq!(fine as u64 + gone, m0 as u64, "what dried is booked, exactly");
    // With any rate left, the last quanta go too.
    let mut w = 3u32;
    for _ in 0..10 {
        w -= evaporate(w, 1e-3, 1.0 / 60.0);
    }
    assert_eq!(w, 0, "hair dries completely");
}

#[test]
fn a_particle_never_gives_more_than_it_has() {
    let m = to_quanta(1.0e-5);
    // 50 hair points each asking for a good part of it.
    let demands: Vec<u32> = (0..50)
        .map(|i| absorb_demand(m, 0.2 + 0.01 * i as f32, 0.1, 1e3, 0.01))
        .collect();
    let total: u64 = demands.iter().map(|&d| d as u64).sum();
    assert!(total > m as u64, "the test asks for more than the particle holds");
    let given: u64 = demands.iter().map(|&d| grant(m, d, total) as u64).sum();
    assert!(given <= m as u64, "never more than it has");
    assert!(
        given + 50 > m as u64,
        "all but the rounding of 50 shares: {given} of {m}"
    );
    // A modest demand is granted in full.
    assert_eq!(grant(m, 7, 100), 7);
    // Saturated hair, or a particle at r_max, asks for nothing.
    assert_eq!(absorb_demand(m, 1.0, 1.0, ABSORB_RATE, 0.01), 0);
    assert_eq!(absorb_demand(m, 0.0, 0.0, ABSORB_RATE, 0.01), 0);
    // The default takes most of a touching drop in a quarter second (1 - e^-5).
    let mut left = m;
    for _ in 0..15 {
        left -= absorb_demand(left, 1.0, 0.0, ABSORB_RATE, 1.0 / 60.0);
    }
    assert!(left < m / 100, "{left}");
}

/// §2: a point's share of absorption is the hair it stands for over `ABSORB_LENGTH`, so a
/// strand's shares sum to its length over `ABSORB_LENGTH` at any sampling (uneven segments
/// included), a 2 cm segment's inner point takes the substep's take unchanged, and no point
/// takes more than the whole particle.
#[test]
fn absorption_shares_follow_the_hair_not_the_points() {
    for segments in [vec![0.02f32; 5], vec![0.005; 20], vec![0.001, 0.03, 0.004, 0.06, 0.005]] {
        let n = segments.len() + 1;
        let total: f32 = (0..n)
            .map(|i| {
                let before = if i > 0 { segments[i - 1] } else { 0.0 };
                absorb_share(before, segments.get(i).copied().unwrap_or(0.0))
            })
            .sum();
        let length: f32 = segments.iter().sum();
        assert!(
            (total - length / ABSORB_LENGTH).abs() < 1e-5,
            "{segments:?}: shares sum to {total}, length over ABSORB_LENGTH {}",
            length / ABSORB_LENGTH
        );
    }
    assert_eq!(absorb_share(0.02, 0.02), 1.0);
    let take = absorb_take(ABSORB_RATE, 1.0 / 240.0);
    assert_eq!(absorb_take_at(take, 1.0), take);
    assert_eq!(absorb_take_at(take, 0.5), take * 0.5);
    assert_eq!(absorb_take_at(take, 1.0e6), 1.0, "never more than the whole particle");
    assert_eq!(absorb_take_at(take, 0.0), 0.0);
}

#[test]
fn flow_conserves_water_and_drains_a_hanging_strand_to_its_tip() {
    let n = 16;
    let g = Vec3::new(0.0, 0.0, -9.81);
    let x: Vec<Vec3> = (0..n).map(|i| Vec3::new(0.0, 0.0, -0.01 * i as f32)).collect();
    let a = vec![Vec3::ZERO; n];
    let none = vec![0u32; n];
    let mut held = vec![to_quanta(1.0e-6); n];
    let total: u64 = held.iter().map(|&w| w as u64).sum();
    for _ in 0..2000 {
        flow_strand(&mut held, &none, &x, &a, g, SPEED, 1.0 / 60.0);
        assert_eq!(held.iter().map(|&w| w as u64).sum::<u64>(), total, "conserved exactly");
    }
    assert!(
        held[n - 1] as f64 > 0.99 * total as f64,
        "with no hold limit, the tip holds it all: {:?}",
        &held[n - 3..]
    );
    // A horizontal strand under vertical gravity does not move its water.
    let flat: Vec<Vec3> = (0..n).map(|i| Vec3::new(0.01 * i as f32, 0.0, 0.0)).collect();
    let before: Vec<u32> = (0..n as u32).map(|i| 1000 * (i + 1)).collect();
    let mut w = before.clone();
    flow_strand(&mut w, &none, &flat, &a, g, SPEED, 1.0 / 60.0);
    assert_eq!(w, before);
    // A strand accelerated downward at g (free fall) feels no gravity along it: no flow either.
    let fall = vec![g; n];
    let mut w2 = before.clone();
    flow_strand(&mut w2, &none, &x, &fall, g, SPEED, 1.0 / 60.0);
    assert_eq!(w2, before);
    // A step long enough to send more than a point holds sends what it holds, no more.
    let mut w3 = before.clone();
    flow_strand(&mut w3, &none, &x, &a, g, SPEED, 10.0);
    assert_eq!(
        w3.iter().map(|&v| v as u64).sum::<u64>(),
        before.iter().map(|&v| v as u64).sum::<u64>()
    );
    assert_eq!(w3[0], 0, "the root sent everything");
}

/// docs/WET_MODEL.md §6: only the water above a point's hold limit runs. A hanging strand
/// holding less than its limits keeps every quantum where it is, however long it hangs; one
/// soaked past them runs the excess to its tip, and every point above keeps its limit (to
/// the few quanta a step's rounding leaves).
#[test]
fn only_water_above_the_hold_limit_runs() {
    let n = 16;
    let g = Vec3::new(0.0, 0.0, -9.81);
    let x: Vec<Vec3> = (0..n).map(|i| Vec3::new(0.0, 0.0, -0.01 * i as f32)).collect();
    let a = vec![Vec3::ZERO; n];
    let hold = vec![to_quanta(1.3e-6); n];
    let below: Vec<u32> = (0..n).map(|i| to_quanta(1.0e-6) + 1000 * i as u32).collect();
    let mut w = below.clone();
    for _ in 0..600 {
        flow_strand(&mut w, &hold, &x, &a, g, SPEED, 1.0 / 60.0);
    }
    assert_eq!(w, below, "water within the hold limits stays put");
    // Twice the limits: the excess runs down, all of it but a step's rounding.
    let mut w = vec![2 * hold[0]; n];
    let total: u64 = w.iter().map(|&q| q as u64).sum();
    for _ in 0..6000 {
        flow_strand(&mut w, &hold, &x, &a, g, SPEED, 1.0 / 60.0);
    }
    assert_eq!(w.iter().map(|&q| q as u64).sum::<u64>(), total, "conserved exactly");
    // A point's send rounds down to 0 below l / (h speed) = 6 quanta above its limit.
    for (i, &q) in w[..n - 1].iter().enumerate() {
        assert!(
            (hold[i]..=hold[i] + 6).contains(&q),
            "point {i} keeps its limit: {q} vs {}",
            hold[i]
        );
    }
    let excess = total - hold.iter().map(|&q| q as u64).sum::<u64>();
    assert!(
        w[n - 1] as u64 - hold[n - 1] as u64 > excess - 6 * n as u64,
        "the tip gathers the excess"
    );
}

/// The flow law's extremes: segments of a micrometre beside ones of 2 cm (each sends
/// `h speed / l` of its running water, here 1,700 times all of it), points flung at 10⁶ g, and
/// counts near the top of a `u32`. The strand's total stays exact and no count wraps, step
/// after step; a segment of no length sends nothing across it.
#[test]
fn flow_stays_exact_across_tiny_segments_and_violent_accelerations() {
    let n = 12;
    let g = Vec3::new(0.0, 0.0, -9.81);
    let mut z = 0.0f32;
    let x: Vec<Vec3> = (0..n)
        .map(|i| {
            let p = Vec3::new(0.0, 0.0, z);
            z -= [0.02, 1.0e-6, 0.0][i % 3];
            p
        })
        .collect();
    let hold = vec![1_000u32; n];
    let mut held: Vec<u32> = (0..n).map(|i| u32::MAX / 3 + 7 * i as u32).collect();
    let total: u64 = held.iter().map(|&q| q as u64).sum();
    for step in 0..200 {
        // Flung up and down the strand by turns, harder than anything a frame makes.
        let s = if step % 2 == 0 { 1.0e7 } else { -1.0e7 };
        let a: Vec<Vec3> = (0..n).map(|i| Vec3::new(0.0, 0.0, s * (1.0 + i as f32))).collect();
        flow_strand(&mut held, &hold, &x, &a, g, SPEED, 1.0 / 60.0);
        let sum: u64 = held.iter().map(|&q| q as u64).sum();
        assert_eq!(sum, total, "step {step}: conserved exactly: {held:?}");
        assert!(held.iter().all(|&q| q as u64 <= total), "step {step}: no count wrapped");
        if step == 0 {
            // Flung up, the water is thrown down the strand: the root, asked for 10⁵ times
            // what may run, sends all of it and keeps its hold limit.
            assert_eq!(held[0], hold[0], "{held:?}");
        }
    }
    // Two points that coincide: the water in them stays on its side of them.
    let same = vec![Vec3::ZERO; 2];
    let mut w = vec![5_000u32, 3_000];
    flow_strand(&mut w, &[0, 0], &same, &[Vec3::ZERO; 2], g, SPEED, 1.0 / 60.0);
    assert_eq!(w, [5_000, 3_000]);
}

#[test]
fn drops_leave_only_above_the_hold_limit_and_take_the_excess() {
    let cap = hold_limit(1.0e-5, 0.3, 0.7);
    assert_eq!(cap, to_quanta(1.0e-5));
    let min = to_quanta(MIN_DROP_MASS as f64);
    assert_eq!(drip(cap, cap, min), 0);
    assert_eq!(drip(cap + min / 2, cap, min), 0, "too small yet");
    assert_eq!(drip(cap + 2 * min, cap, min), 2 * min);
    assert_eq!(drip(cap / 2, cap, min), 0);
}

#[test]
fn capacity_is_per_metre_of_hair_whatever_the_sampling() {
    // A 0.4 m strand of 1 g/m sampled at 6, 16 and 64 points: each point's dry mass is its
    // share of the length; the strand's capacity is the same (to the rounding of each point).
    for n in [6usize, 16, 64] {
        let seg = 0.4 / (n - 1) as f32;
        let total: u64 = (0..n)
            .map(|i| {
                let share = if i == 0 || i == n - 1 { 0.5 * seg } else { seg };
                capacity(1.0e-3 * share, CAPACITY_RATIO) as u64
            })
            .sum();
        assert!(
            rel(to_kg(total as u32), 0.4 * 1.0e-3 * 0.3) < 1e-5,
            "{n} points: {total}"
        );
    }
    assert_eq!(saturation(5, 0), 0.0, "nothing to hold, nothing held");
    assert_eq!(saturation(3, 6), 0.5);
    assert_eq!(to_quanta(-1.0), 0);
    assert_eq!(to_quanta(f64::NAN), 0);
    assert_eq!(to_quanta(1.0), u32::MAX, "a kilogram saturates the count");
    assert!(
        to_quanta(MAX_WATER_MASS) <= u32::MAX / 2 + 1,
        "half the count is headroom"
    );
    assert!(
        to_kg(to_quanta(2.0e-3)) <= MAX_WATER_MASS,
        "a point of 2 g capacity fits"
    );
}

#[test]
fn limpness_follows_its_curve() {
    assert_eq!(bend_scale(0.0, WET_BEND_RATIO), 1.0);
    assert_eq!(bend_scale(1.0, WET_BEND_RATIO), 0.5);
    assert_eq!(bend_scale(0.5, WET_BEND_RATIO), 0.75);
    assert_eq!(
        bend_scale(3.0, WET_BEND_RATIO),
        0.5,
        "over capacity is as limp as saturated"
    );
}

#[test]
fn bridges_pull_hardest_halfway_and_let_go_at_contact_length_and_when_dry() {
    let kappa = 2.0 * SURFACE_TENSION;
    let d_b = 1e-3;
    let c = bridge_stiffness(kappa, 0.02, 1.0, 1.0, d_b);
    let pull = |r: f32| bridge_scale(c, r, d_b) * r;
    assert!(
        (pull(0.5 * d_b) - kappa * 0.02).abs() < 1e-7,
        "peak kappa l s at d_b / 2"
    );
    assert!(pull(0.3 * d_b) < pull(0.5 * d_b) && pull(0.7 * d_b) < pull(0.5 * d_b));
    assert_eq!(pull(0.0), 0.0, "no pull once the points meet");
    assert_eq!(bridge_scale(c, d_b, d_b), 0.0, "none at the bridge length");
    assert_eq!(
        bridge_stiffness(kappa, 0.02, 0.0, 1.0, d_b),
        0.0,
        "a dry point holds no bridge"
    );
    assert_eq!(
        bridge_stiffness(kappa, 0.02, 0.3, 0.8, d_b),
        bridge_stiffness(kappa, 0.02, 0.8, 0.3, d_b),
        "the same both ways"
    );
    let half = bridge_stiffness(kappa, 0.02, 0.5, 1.0, d_b);
    assert!((half / c - 0.5).abs() < 1e-6, "pull grows with the drier point's water");
}

#[test]
fn gusts_are_deterministic_and_average_to_the_wind() {
    let w0 = Vec3::new(2.0, 0.0, 0.0);
    assert_eq!(gust(w0, 0.5, 7, 3.25), gust(w0, 0.5, 7, 3.25));
    assert_ne!(gust(w0, 0.5, 7, 3.25), gust(w0, 0.5, 8, 3.25), "the seed matters");
    assert_eq!(gust(w0, 0.0, 7, 3.25), w0, "no gusts, steady wind");
    let mean: f64 = (0..60_000)
        .map(|k| gust(w0, 0.5, 7, k as f64 / 60.0).x as f64)
        .sum::<f64>()
        / 60_000.0;
    assert!((mean - 2.0).abs() < 0.05, "mean over 1,000 s {mean}");
    let max = (0..6000)
        .map(|k| gust(w0, 0.5, 7, k as f64 / 60.0).x)
        .fold(0.0f32, f32::max);
    assert!(max <= 3.0 + 1e-5, "never above w0 (1 + amplitude): {max}");
}
