//! The copy path (issue 13, item 13): what `write_vertices` writes equals, bit for bit, the
//! definition computed point by point from the simulation's state, for every attribute set,
//! ragged strands (shorter and longer than the writer's 16-row stage), wet points and every
//! thread count. The writer lays 8 strands out at once with vector code; this is the check
//! that none of that shows.

use glam::Vec3;
use wethair::groom::Groom;
use wethair::scenes::{on_hair, Lcg};
use wethair::{Backend, SimParams, Simulation, VertexAttributes};

/// 29 strands of 2 to 40 points (so some blocks have padding lanes, some strands span three
/// stage passes), hanging off a sphere, one of them with no length.
fn ragged() -> Groom {
    let mut rng = Lcg(7);
    let (mut pos, mut counts) = (Vec::new(), Vec::new());
    for s in 0..29u32 {
        let n = 2 + (s * 13) % 39;
        let dir = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, 0.3).normalize();
        for i in 0..n {
            pos.push(dir * (0.1 + 0.01 * i as f32));
        }
        counts.push(n);
    }
    // Strand 0 (2 points) has both points pinned on the same spot: a zero-length difference,
    // whose tangent is +z.
    pos[1] = pos[0];
    let mut pinned = vec![false; pos.len()];
    let mut first = 0;
    for &n in &counts {
        pinned[first] = true;
        first += n as usize;
    }
    pinned[1] = true;
    Groom::new(pos, &counts, Some(pinned), None, 1e-3).expect("groom")
}

/// The definition: position, the unit central difference of the neighbours (one-sided at the
/// ends, +z where it has no length), wetness; in the host's order, only the requested ones.
fn expected(groom: &Groom, states: &[(Vec3, Vec3, f32)], attrs: VertexAttributes) -> Vec<f32> {
    let mut out = Vec::new();
    for s in 0..groom.strand_count() {
        let r = groom.strand_range(s);
        for i in r.clone() {
            let a = states[i.saturating_sub(1).max(r.start)].0;
            let c = states[(i + 1).min(r.end - 1)].0;
            let t = (c - a).normalize_or(Vec3::Z);
            for bit in [
                VertexAttributes::POSITION,
                VertexAttributes::TANGENT,
                VertexAttributes::WETNESS,
            ] {
                if attrs.0 & bit == 0 {
                    continue;
                }
                match bit {
                    VertexAttributes::POSITION => out.extend(states[i].0.to_array()),
                    VertexAttributes::TANGENT => out.extend(t.to_array()),
                    _ => out.push(states[i].2),
                }
            }
        }
    }
    out
}

#[test]
fn vertices_equal_their_definition_bit_for_bit() {
    let groom = ragged();
    let hair = groom.positions().to_vec();
    for bits in 1..=7u32 {
        for threads in [1, 2, 3] {
            let mut p = SimParams::paper();
            p.backend = Backend::CPU;
            p.threads = threads;
            p.attributes = VertexAttributes(bits);
            let mut sim = Simulation::new(&groom, p).expect("sim");
            // Water on the hair, so wetness differs per point.
            let drops = on_hair(&hair, 60, &mut Lcg(3));
            sim.add_water(&drops, &vec![Vec3::ZERO; drops.len()]).expect("water");
            for _ in 0..12 {
                sim.step(1.0 / 60.0).expect("step");
            }
            let states = sim.point_states().expect("states");
            assert!(states.iter().any(|s| s.2 > 0.0), "some points are wet");
            assert_eq!(states[0].0, states[1].0, "strand 0 has no length");
            let want = expected(&groom, &states, VertexAttributes(bits));
            // One float more than needed, poisoned: nothing past the vertices is written.
            let mut got = vec![f32::NAN; want.len() + 1];
            let n = sim.write_vertices(&mut got).expect("vertices");
            assert_eq!(n, want.len(), "attributes {bits}");
            for (k, (g, w)) in got.iter().zip(&want).enumerate() {
                assert_eq!(
                    g.to_bits(),
                    w.to_bits(),
                    "attributes {bits}, {threads} threads, float {k}"
                );
            }
            assert!(got[n].is_nan(), "the float past the vertices is untouched");
        }
    }
}
