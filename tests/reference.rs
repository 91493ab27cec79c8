//! The f64 reference converges: halving its step changes the 1 s result by less than 1e-9 m
//! (the report's chain scene; the wet slices are checked by the report command, which prints
//! the same figure for each scene), and it agrees with the f32 backend at fine steps.

use wethair::reference::Reference;
use wethair::scenes::swinging_chain;
use wethair::Simulation;

#[test]
fn reference_halving_the_step_changes_less_than_1e_9() {
    let sc = swinging_chain();
    let mut a = Reference::new(&sc.groom, &sc.params, &sc.water);
    let mut b = a.clone();
    a.run_to(1.0, 1.0 / 16_000.0);
    b.run_to(1.0, 1.0 / 32_000.0);
    let diff = a
        .hair_positions()
        .iter()
        .zip(b.hair_positions())
        .map(|(p, q)| (*p - *q).length())
        .fold(0.0, f64::max);
    assert!(diff < 1e-9, "halving the reference step moved a point by {diff} m");
}

#[test]
fn backend_converges_to_the_reference() {
    let sc = swinging_chain();
    let mut r = Reference::new(&sc.groom, &sc.params, &sc.water);
    r.run_to(1.0, 1.0 / 16_000.0);
    let mut errs = vec![];
    for substeps in [4, 16, 64] {
        let mut sim = Simulation::new(
            &sc.groom,
            wethair::SimParams {
                substeps,
                threads: 1,
                ..sc.params.clone()
            },
        )
        .unwrap();
        for _ in 0..60 {
            sim.step(1.0 / 60.0).unwrap();
        }
        let e = sim
            .positions()
            .iter()
            .zip(r.hair_positions())
            .map(|(p, q)| (p.as_dvec3() - *q).length())
            .fold(0.0, f64::max);
        errs.push(e);
    }
    // Symplectic Euler is first order: 4x the substeps, about 4x less error.
    assert!(errs[1] < errs[0] / 2.5 && errs[2] < errs[1] / 2.5, "errors {errs:?}");
    assert!(errs[2] < 1e-3, "errors {errs:?}");
}

/// An ensemble member (the report's chaotic scenes) moves the free points only: pinned roots
/// stay on the head and the rest lengths stay the groom's: a perturbed state, not a
/// different model.
#[test]
fn a_moved_reference_moves_its_free_points_only() {
    let sc = swinging_chain();
    let base = sc.reference();
    let nudge = |i: usize| glam::DVec3::new(0.0, 1e-7 * (i + 1) as f64, 0.0);
    let moved = sc.reference().moved(nudge);
    let mut free = 0;
    for (i, (p, q)) in base.hair_positions().iter().zip(moved.hair_positions()).enumerate() {
        if sc.groom.pinned()[i] {
            assert_eq!(p, q, "pinned point {i} moved");
        } else {
            free += 1;
            assert!(
                ((*q - *p) - nudge(i)).length() < 1e-15,
                "point {i} moved by {}",
                *q - *p
            );
        }
    }
    assert!(free > 0);
    // The energy moves by no more than the nudges' own work (gravity's m g δ and the springs'
    // k δ² for δ of 1e-7 m), far under a nanojoule.
    let extra = moved.energy() - base.energy();
    assert!(extra.abs() < 1e-9, "the nudge changed the energy by {extra} J");
    // And a zero move is no move at all.
    let mut a = sc.reference();
    let mut b = sc.reference().moved(|_| glam::DVec3::ZERO);
    a.run_to(0.1, 1.0 / 16_000.0);
    b.run_to(0.1, 1.0 / 16_000.0);
    assert_eq!(a.hair_positions(), b.hair_positions());
}
