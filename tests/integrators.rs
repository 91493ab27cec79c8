//! The integrators: each stays sane on the paper scene; implicit Euler and XPBD survive springs
//! 10^6 times stiffer than symplectic Euler's limit at one 1/30 s substep; AUTO picks the
//! cheapest stable one; implicit Euler finds the same static equilibrium.

use glam::Vec3;
use wethair::groom::{paper_scene, Groom};
use wethair::plan::Pass;
use wethair::{Error, Integrator, SimParams, Simulation, SpringParams};

const ALL: [Integrator; 3] = [
    Integrator::SYMPLECTIC_EULER,
    Integrator::IMPLICIT_EULER,
    Integrator::XPBD,
];

fn strand_lengths(sim: &Simulation, points: usize) -> Vec<f32> {
    sim.positions()
        .chunks(points)
        .map(|s| s.windows(2).map(|w| (w[1] - w[0]).length()).sum())
        .collect()
}

#[test]
fn every_integrator_keeps_the_paper_scene_sane() {
    let groom = paper_scene(1000, 6).unwrap();
    for integrator in ALL {
        let mut sim = Simulation::new(
            &groom,
            SimParams {
                integrator,
                ..SimParams::paper_scene_with_head()
            },
        )
        .unwrap();
        for _ in 0..120 {
            sim.step(1.0 / 60.0).unwrap();
        }
        let x = sim.positions();
        assert!(x.iter().all(|p| p.is_finite()));
        let r = x.iter().map(|p| p.length()).fold(0.0, f32::max);
        assert!(
            r < 0.21,
            "{integrator:?}: a point at {r} m (strands are 0.1 m on a 0.1 m head)"
        );
        // Gravity pulls the tips down: their mean height drops below the roots'.
        let tips: f32 = x.chunks(6).map(|s| s[5].z - s[0].z).sum::<f32>() / 1000.0;
        assert!(tips < 0.0, "{integrator:?}: tips did not fall ({tips})");
    }
}

/// The acceptance case: springs 10^6 times stiffer than symplectic Euler's limit, one substep
/// of 1/30 s. Implicit Euler (the recommended integrator, 2 Newton iterations) stays finite, keeps its energy
/// bounded (within 1% of M g L above the start), and keeps every strand within 5% of its rest
/// length; XPBD stays finite and
/// bounded; symplectic Euler diverges and reports it.
#[test]
fn stiff_springs_survive_one_frame_rate_substep() {
    // Symplectic Euler's limit at h = 1/30 s: h² 4k/m = 4  =>  k = m / h² = 0.9 N/m.
    let h = 1.0 / 30.0;
    let k = 1e6 * 1e-3 / (h * h);
    let groom = paper_scene(200, 6).unwrap();
    let rest = strand_lengths(&Simulation::new(&groom, SimParams::paper()).unwrap(), 6);
    let stiff = |integrator| SimParams {
        integrator,
        // The recommended setting for stiff scenes: two Newton iterations per substep.
        solver_iterations: 2,
        substeps: 1,
        stretch: SpringParams {
            stiffness: k,
            damping: 0.0,
        },
        bend: SpringParams {
            stiffness: k,
            damping: 0.0,
        },
        ..SimParams::paper()
    };
    let mut sim = Simulation::new(&groom, stiff(Integrator::IMPLICIT_EULER)).unwrap();
    let e0 = sim.energy().total();
    // Bounded: never more than 1% of the hair's weight times its length (M g L) above the
    // start, where a blow-up would be orders of magnitude above it. (One Newton iteration is
    // not the exact minimiser, so the energy may tick up slightly before damping takes it.)
    let mgl = 200.0 * 5.0 * 1e-3 * 9.81 * 0.1;
    let mut e_max = e0;
    for _ in 0..90 {
        sim.step(h).unwrap();
        e_max = e_max.max(sim.energy().total());
    }
    assert!(
        e_max <= e0 + 0.01 * mgl,
        "energy rose from {e0} to {e_max} J (M g L = {mgl} J)"
    );
    assert!(sim.positions().iter().all(|p| p.is_finite()));
    for (s, (l, l0)) in strand_lengths(&sim, 6).iter().zip(&rest).enumerate() {
        assert!((l / l0 - 1.0).abs() < 0.05, "strand {s} length {l} vs rest {l0}");
    }

    let mut xpbd = Simulation::new(&groom, stiff(Integrator::XPBD)).unwrap();
    for _ in 0..90 {
        xpbd.step(h).unwrap();
    }
    assert!(
        xpbd.positions().iter().all(|p| p.is_finite() && p.length() < 0.5),
        "XPBD left the strands' reach"
    );

    // The explicit method at the same settings diverges, and says so.
    let mut sim = Simulation::new(&groom, stiff(Integrator::SYMPLECTIC_EULER)).unwrap();
    let err = (0..90).find_map(|_| sim.step(h).err());
    assert!(
        matches!(err, Some(Error::Unstable { .. })),
        "symplectic Euler should diverge: {err:?}"
    );
}

#[test]
fn auto_picks_the_cheapest_stable_integrator() {
    let groom = paper_scene(100, 6).unwrap();
    let paper = Simulation::new(
        &groom,
        SimParams {
            integrator: Integrator::AUTO,
            ..SimParams::paper()
        },
    )
    .unwrap();
    assert_eq!(
        paper.stats().integrator,
        Integrator::SYMPLECTIC_EULER,
        "the paper scene is stable at 1/240 s"
    );
    let stiff = SimParams {
        integrator: Integrator::AUTO,
        stretch: SpringParams {
            stiffness: 4000.0,
            damping: 0.0,
        },
        ..SimParams::paper()
    };
    let sim = Simulation::new(&groom, stiff).unwrap();
    assert_eq!(sim.stats().integrator, Integrator::IMPLICIT_EULER);
    assert_eq!(sim.passes(), vec![Pass::ImplicitSolve]);
    let xpbd = Simulation::new(
        &groom,
        SimParams {
            integrator: Integrator::XPBD,
            ..SimParams::paper()
        },
    )
    .unwrap();
    assert_eq!(xpbd.passes(), vec![Pass::Integrate, Pass::ProjectConstraints]);
}

/// Implicit Euler settles a hanging chain at the same analytic static stretch (1%).
#[test]
fn implicit_hanging_chain_settles_at_static_stretch() {
    let (n, seg, m, k, g) = (6usize, 0.02f32, 1e-3f32, 40.0f32, 9.81f32);
    let pos: Vec<Vec3> = (0..n).map(|i| Vec3::new(0.0, 0.0, -(i as f32) * seg)).collect();
    let groom = Groom::new(pos, &[n as u32], None, None, m).unwrap();
    let params = SimParams {
        integrator: Integrator::IMPLICIT_EULER,
        stretch: SpringParams {
            stiffness: k,
            damping: 0.02,
        },
        bend: SpringParams {
            stiffness: 0.0,
            damping: 0.0,
        },
        substeps: 1,
        ..SimParams::paper()
    };
    let mut sim = Simulation::new(&groom, params).unwrap();
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
