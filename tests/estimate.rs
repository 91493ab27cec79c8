//! The live error estimate (`SimParams::error_estimate_stride`, `Stats::error_estimate`):
//! against the true error from the f64 reference, on the scenes where pointwise error means
//! something, and withheld where strands couple.

use glam::Vec3;
use wethair::reference::Reference;
use wethair::scenes::{paper_slice, soaked_chain, swinging_chain, ReportScene};
use wethair::{Backend, Integrator, SimParams, Simulation};

/// Runs `sc` for `t` s at 60 Hz and returns (estimated RMS error, true RMS error).
fn estimate_and_truth(sc: &ReportScene, integrator: Integrator, substeps: u32, stride: u32, t: f64) -> (f32, f64) {
    let params = SimParams {
        integrator,
        solver_iterations: 2,
        substeps,
        threads: 1,
        backend: Backend::CPU,
        error_estimate_stride: stride,
        ..sc.params.clone()
    };
    let mut sim = Simulation::new(&sc.groom, params).expect("valid");
    let frames = (t * 60.0).round() as usize;
    for _ in 0..frames {
        sim.step(1.0 / 60.0).expect("stable");
    }
    let est = sim.stats().error_estimate.expect("estimated on a dry scene").rms;
    let mut r = Reference::new(&sc.groom, &sc.params, &sc.water);
    r.run_to(frames as f64 / 60.0, 1.0 / 32_000.0);
    let x = sim.positions();
    let sq: f64 = x
        .iter()
        .zip(r.hair_positions())
        .map(|(p, q)| (p.as_dvec3() - *q).length_squared())
        .sum();
    (est, (sq / x.len() as f64).sqrt())
}

fn assert_within_3x(what: &str, (est, truth): (f32, f64)) {
    let ratio = est as f64 / truth;
    assert!(
        (1.0 / 3.0..=3.0).contains(&ratio),
        "{what}: estimate {est:.3e} m, true RMS error {truth:.3e} m (ratio {ratio:.2})"
    );
}

#[test]
fn the_estimate_is_within_3x_of_the_true_error_on_the_chain() {
    let sc = swinging_chain();
    for (i, n) in [
        (Integrator::SYMPLECTIC_EULER, 8),
        (Integrator::SYMPLECTIC_EULER, 32),
        (Integrator::IMPLICIT_EULER, 8),
        (Integrator::BDF2, 8),
    ] {
        assert_within_3x(
            &format!("chain, {i:?} at {n} substeps"),
            estimate_and_truth(&sc, i, n, 1, 1.0),
        );
    }
}

#[test]
fn the_estimate_is_within_3x_of_the_true_error_on_the_dry_patch() {
    let sc = paper_slice(12, 0, 1.0);
    for (i, n, stride) in [
        (Integrator::SYMPLECTIC_EULER, 4, 1),
        (Integrator::SYMPLECTIC_EULER, 4, 4),
        (Integrator::IMPLICIT_EULER, 4, 1),
        (Integrator::BDF2, 4, 1),
    ] {
        assert_within_3x(
            &format!("dry patch, {i:?} at {n} substeps, every {stride}. strand"),
            estimate_and_truth(&sc, i, n, stride, 0.5),
        );
    }
}

#[test]
fn the_estimate_falls_with_the_integrators_order() {
    // Doubling the substeps at least halves a first-order method's estimate and quarters
    // BDF2's (symplectic Euler does better on the chain: its positions are a leapfrog's, whose
    // only first-order error is the start, which the damping forgets).
    let sc = swinging_chain();
    for (i, expect) in [(Integrator::SYMPLECTIC_EULER, 2.0), (Integrator::BDF2, 4.0)] {
        let a = estimate_and_truth(&sc, i, 32, 1, 1.0).0;
        let b = estimate_and_truth(&sc, i, 64, 1, 1.0).0;
        let ratio = a / b;
        assert!(
            ratio >= expect * 0.8,
            "{i:?}: 32 substeps {a:.3e} m, 64 substeps {b:.3e} m: ratio {ratio:.2}, expected at least {expect}"
        );
    }
}

#[test]
fn no_estimate_unless_asked_and_none_while_water_couples_strands() {
    let sc = paper_slice(8, 0, 1.0);
    let mut off = Simulation::new(&sc.groom, sc.params.clone()).unwrap();
    off.step(1.0 / 60.0).unwrap();
    assert_eq!(off.stats().error_estimate, None, "off by default");

    let params = SimParams {
        error_estimate_stride: 2,
        ..sc.params.clone()
    };
    let mut sim = Simulation::new(&sc.groom, params).unwrap();
    assert_eq!(
        sim.stats().error_estimate.map(|e| e.rms),
        Some(0.0),
        "at rest, before any step, nothing is off"
    );
    sim.step(1.0 / 60.0).unwrap();
    let e = sim.stats().error_estimate.expect("dry: estimated");
    assert!(e.rms > 0.0 && e.max >= e.rms && e.max.is_finite(), "{e:?}");
    let tip = sc.groom.positions()[5];
    sim.add_water(&[tip + Vec3::new(0.0, 0.0, 0.003)], &[]).unwrap();
    sim.step(1.0 / 60.0).unwrap();
    assert_eq!(sim.stats().error_estimate, None, "water couples strands");
    sim.clear_water().unwrap();
    sim.step(1.0 / 60.0).unwrap();
    assert_eq!(sim.stats().error_estimate, None, "the water's pull stays in the state");
    sim.reset().unwrap();
    sim.step(1.0 / 60.0).unwrap();
    assert_eq!(
        sim.stats().error_estimate,
        Some(e),
        "a reset starts the shadow over: the same first step gives the same estimate"
    );
}

#[test]
fn the_shadow_follows_the_head() {
    // A moving head moves the roots of both runs; the estimate stays small (the roots follow
    // the head exactly in both) and tracks the motion's error, not the head's displacement.
    let sc = paper_slice(8, 0, 1.0);
    let params = SimParams {
        error_estimate_stride: 1,
        substeps: 16,
        ..sc.params.clone()
    };
    let mut sim = Simulation::new(&sc.groom, params).unwrap();
    for f in 0..30 {
        let x = 0.05 * (f as f32 * 0.2).sin();
        sim.set_head_transform(glam::Mat4::from_translation(Vec3::new(x, 0.0, 0.0)))
            .unwrap();
        sim.step(1.0 / 60.0).unwrap();
    }
    let e = sim.stats().error_estimate.unwrap();
    assert!(e.max < 5e-3, "{e:?}: the shadow must move with the head");
}

/// Runs `sc` for `t` s at 60 Hz under an error budget; returns the substeps chosen at the end,
/// the largest true point error (against the f64 reference) and the integrators and substeps
/// seen on the way.
fn budgeted(
    sc: &ReportScene,
    integrator: Integrator,
    substeps: u32,
    tolerance: f32,
    max_substeps: u32,
    t: f64,
) -> (u32, f64, Vec<(Integrator, u32)>) {
    let params = SimParams {
        integrator,
        solver_iterations: 2,
        substeps,
        threads: 1,
        backend: Backend::CPU,
        tolerance,
        max_substeps,
        error_estimate_stride: 1,
        ..sc.params.clone()
    };
    let mut sim = Simulation::new(&sc.groom, params).expect("valid");
    let frames = (t * 60.0).round() as usize;
    let mut seen = vec![];
    for _ in 0..frames {
        sim.step(1.0 / 60.0).expect("stable");
        let s = sim.stats();
        let now = (s.integrator, s.substeps);
        if seen.last() != Some(&now) {
            seen.push(now);
        }
    }
    let mut r = Reference::new(&sc.groom, &sc.params, &sc.water);
    r.run_to(frames as f64 / 60.0, 1.0 / 32_000.0);
    let max = sim
        .positions()
        .iter()
        .zip(r.hair_positions())
        .map(|(p, q)| (p.as_dvec3() - *q).length())
        .fold(0.0, f64::max);
    eprintln!("{integrator:?} under {tolerance:e} m: chose {seen:?}, largest true error {max:.3e} m");
    (seen[seen.len() - 1].1, max, seen)
}

#[test]
fn a_tight_budget_raises_the_substeps_until_the_error_fits() {
    let sc = paper_slice(12, 0, 1.0);
    let free = estimate_and_truth(&sc, Integrator::SYMPLECTIC_EULER, 4, 1, 1.0);
    let tolerance = 1e-4;
    let (n, err, seen) = budgeted(&sc, Integrator::SYMPLECTIC_EULER, 4, tolerance, 128, 1.5);
    assert!(n > 4, "substeps {seen:?}: the 4-substep run's error is {free:?}");
    assert!(
        err <= 2.0 * tolerance as f64,
        "budget {tolerance:e} m: largest true error {err:.3e} m after choosing {seen:?}"
    );
}

#[test]
fn a_loose_budget_lets_an_implicit_integrator_drop_substeps() {
    let sc = paper_slice(12, 0, 1.0);
    let tolerance = 1e-3;
    let (n, err, seen) = budgeted(&sc, Integrator::BDF2, 8, tolerance, 128, 1.0);
    assert!(n < 8, "BDF2 kept {seen:?} substeps under a {tolerance:e} m budget");
    assert!(
        err <= 2.0 * tolerance as f64,
        "budget {tolerance:e} m: largest true error {err:.3e} m after choosing {seen:?}"
    );
}

#[test]
fn auto_moves_to_bdf2_where_stability_alone_makes_symplectic_euler_dear() {
    // Springs 4000x the paper's: symplectic Euler needs about 256 substeps of a 60 Hz frame
    // to be stable at all, BDF2 far fewer for a 1e-5 m tolerance.
    let sc = paper_slice(12, 0, 4000.0);
    let tolerance = 1e-4;
    let (n, err, seen) = budgeted(&sc, Integrator::AUTO, 256, tolerance, 256, 2.0);
    assert_eq!(
        seen[0],
        (Integrator::SYMPLECTIC_EULER, 256),
        "AUTO starts symplectic where it is stable"
    );
    assert_eq!(seen.last().unwrap().0, Integrator::BDF2, "chose {seen:?}");
    assert!(n <= 3, "BDF2 at {n} substeps costs more than symplectic Euler at 256");
    assert!(
        err <= 2.0 * tolerance as f64,
        "budget {tolerance:e} m: largest true error {err:.3e} m after choosing {seen:?}"
    );
}

#[test]
fn auto_moves_to_symplectic_euler_where_it_is_stable_and_cheaper() {
    let sc = paper_slice(12, 0, 1.0);
    let tolerance = 1e-4;
    // One substep: symplectic Euler is unstable there, so AUTO starts with BDF2.
    let (n, err, seen) = budgeted(&sc, Integrator::AUTO, 1, tolerance, 128, 3.0);
    assert_eq!(seen[0], (Integrator::BDF2, 1), "chose {seen:?}");
    let last = *seen.last().unwrap();
    assert_eq!(last.0, Integrator::SYMPLECTIC_EULER, "chose {seen:?}");
    assert!(
        n < 40,
        "a BDF2 substep costs about 80 symplectic ones here; chose {seen:?}"
    );
    assert!(
        err <= 2.0 * tolerance as f64,
        "budget {tolerance:e} m: largest true error {err:.3e} m after choosing {seen:?}"
    );
}

#[test]
fn a_budget_needs_room_and_a_sane_tolerance() {
    let sc = paper_slice(4, 0, 1.0);
    for (tolerance, max_substeps) in [(f32::NAN, 64), (-1e-3, 64), (f32::INFINITY, 64), (1e-3, 2), (1e-3, 600)] {
        let p = SimParams {
            tolerance,
            max_substeps,
            ..sc.params.clone()
        };
        assert!(
            Simulation::new(&sc.groom, p).is_err(),
            "tolerance {tolerance}, max_substeps {max_substeps} accepted"
        );
    }
}

/// The wet model's weight and limpness against the f64 reference (`Reference::soaked`): the
/// soaked chain converges to it, its energy counts the water, and the estimate follows the
/// true error there as on the dry chain.
#[test]
fn the_soaked_chain_converges_to_the_wet_reference_and_the_estimate_sees_it() {
    let sc = soaked_chain();
    let params = |integrator, substeps| SimParams {
        integrator,
        solver_iterations: 2,
        substeps,
        threads: 1,
        backend: Backend::CPU,
        error_estimate_stride: 1,
        ..sc.params.clone()
    };
    let mut r = sc.reference();
    r.run_to(1.0, 1.0 / 32_000.0);
    let mut dry = swinging_chain().reference();
    dry.run_to(1.0, 1.0 / 32_000.0);
    let rms = |x: &[Vec3], q: &[glam::DVec3]| {
        (x.iter()
            .zip(q)
            .map(|(p, q)| (p.as_dvec3() - *q).length_squared())
            .sum::<f64>()
            / x.len() as f64)
            .sqrt()
    };
    let water_moves = rms(
        &dry.hair_positions().iter().map(|p| p.as_vec3()).collect::<Vec<_>>(),
        r.hair_positions(),
    );
    let mut errs = vec![];
    for (i, n) in [
        (Integrator::SYMPLECTIC_EULER, 16),
        (Integrator::SYMPLECTIC_EULER, 64),
        (Integrator::BDF2, 16),
        (Integrator::BDF2, 64),
    ] {
        let mut sim = sc.simulation(params(i, n)).unwrap();
        for _ in 0..60 {
            sim.step(1.0 / 60.0).unwrap();
        }
        let truth = rms(&sim.positions(), r.hair_positions());
        let est = sim.stats().error_estimate.expect("no particles: estimated").rms;
        assert_within_3x(&format!("soaked chain, {i:?} at {n} substeps"), (est, truth));
        // The energy counts the water's weight, as the reference's does (M g L: the wet
        // chain's weight times its length).
        let mgl = 9.0 * 3e-3 * 9.81 * 0.18;
        let (e_sim, e_ref) = (sim.energy().total(), r.energy());
        assert!(
            (e_sim - e_ref).abs() < 0.02 * mgl,
            "{i:?} at {n} substeps: energy {e_sim} J, reference {e_ref} J"
        );
        errs.push(truth);
    }
    assert!(
        errs[1] < errs[0] / 2.0 && errs[3] < errs[2] / 4.0,
        "converging: {errs:?}"
    );
    assert!(
        water_moves > 10.0 * errs[1],
        "the water's weight and limpness move the chain {water_moves:.2e} m, errors {errs:?}"
    );
}

/// `Simulation::counters` is `stats` without its measures: every counter the same, the
/// clumping measures -1 and no estimate, where `stats` measures all three.
#[test]
fn counters_are_the_stats_without_their_measures() {
    let sc = paper_slice(8, 0, 1.0);
    let params = SimParams {
        error_estimate_stride: 2,
        ..sc.params.clone()
    };
    let mut sim = Simulation::new(&sc.groom, params).unwrap();
    for _ in 0..3 {
        sim.step(1.0 / 60.0).unwrap();
    }
    let (st, c) = (sim.stats(), sim.counters());
    assert!(
        st.clumping > 0.0 && st.clumping_along > 0.0 && st.error_estimate.is_some(),
        "{st:?}"
    );
    assert_eq!((c.clumping, c.clumping_along, c.error_estimate), (-1.0, -1.0, None));
    let measured = wethair::Stats {
        clumping: st.clumping,
        clumping_along: st.clumping_along,
        error_estimate: st.error_estimate,
        ..c
    };
    assert_eq!(measured, st, "the same counters");
    assert_eq!(c.steps, 3);
}
