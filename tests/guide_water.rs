//! Guides hold their followers' water (`physics/bundles.rs`, docs/GUIDES.md "Water"), on both
//! backends: with a tenth of the strands simulated a soak holds the groom's water, each guide
//! hangs as a fully simulated strand with the same water does, and a change of the simulated
//! fraction moves the water with the hair, neither making nor losing a quantum and keeping
//! the groom as wet as it was; and a guide pulls a water particle back with its bundle's hair
//! (eq. 2's reaction), as all the strands it stands for would.

use crate::common::{backends, serial};
use wethair::groom::paper_scene;
use wethair::{Backend, GuideChoice, Guides, HeldWater, SimParams, Simulation};

const DT: f32 = 1.0 / 60.0;

/// The paper scene's parameters with held water, on `backend`. The paper scene's points weigh
/// a gram, so a bundle of them would hold more than one water count holds (2.1 g: its guide
/// then holds no more, `wet::bundle_limits`); here a point holds 5 % of its mass, and a guide
/// may stand for 40 strands. No liquid bridges: they pull strands toward their neighbours,
/// and the neighbours differ with guides.
fn params(backend: Backend, guides: Guides) -> SimParams {
    SimParams {
        backend,
        guides,
        held_water: HeldWater {
            bridge_tension: 0.0,
            capacity_ratio: 0.03,
            free_ratio: 0.02,
            ..HeldWater::ON
        },
        ..SimParams::paper()
    }
}

fn held(sim: &Simulation) -> u64 {
    let l = sim.water_ledger().expect("held water is on");
    assert!(l.balanced(), "{l:?}");
    l.held
}

/// Each vertex's wetness (the default attributes: position, tangent, wetness).
fn wetness(sim: &mut Simulation) -> Vec<f32> {
    let mut v = vec![0.0; sim.vertex_count() * sim.attributes().stride()];
    sim.write_vertices(&mut v).unwrap();
    v.chunks(7).map(|c| c[6]).collect()
}

/// A soak holds the whole groom's water with a tenth of its strands simulated (each guide
/// holds its bundle's), and each guide hangs as the same strand does with every strand
/// simulated: its own share of the water weighs on it, not its bundle's.
#[test]
fn a_tenth_simulated_holds_and_weighs_the_groom_s_water() {
    let _serial = serial();
    let g = paper_scene(1000, 6).unwrap();
    for backend in backends() {
        let mut all = Simulation::new(&g, params(backend, Guides::ALL)).unwrap();
        let mut tenth = Simulation::new(&g, params(backend, Guides::every_nth(10))).unwrap();
        let mut dry = Simulation::new(&g, params(backend, Guides::every_nth(10))).unwrap();
        all.soak(1.0).unwrap();
        tenth.soak(1.0).unwrap();
        let (a, t) = (held(&all), held(&tenth));
        let off = (a as f64 - t as f64).abs() / a as f64;
        eprintln!("{backend:?}: soaked, every strand {a} quanta, a tenth simulated {t} ({off:.1e} apart)");
        // The bundles add to the groom's hair exactly; each point's limit rounds to a quantum.
        assert!(off < 1e-5, "{backend:?}: {t} quanta held against {a}");
        // 30 frames: the paper scene's strands fall and swing wildly, and from frame 60 on
        // a difference in the last bits grows to millimetres (measured: 1.1 µm at frame 30,
        // 0.75 mm at 60, 12 mm at 90, between the same two runs).
        for _ in 0..30 {
            for s in [&mut all, &mut tenth, &mut dry] {
                s.step(DT).unwrap();
            }
        }
        let host = tenth.guide_strands().expect("guides").to_vec();
        let all_tips = all.tips();
        let gap = |s: &Simulation| {
            s.tips()
                .iter()
                .zip(&host)
                .map(|(p, &h)| p.distance(all_tips[h as usize]))
                .fold(0.0f32, f32::max)
        };
        let (wet_gap, dry_gap) = (gap(&tenth), gap(&dry));
        eprintln!(
            "{backend:?}: guide tips from the same strands simulated with all: {wet_gap:e} m soaked, {dry_gap:e} m dry"
        );
        // The water's weight moves the tips: the dry guides show how far, and a guide that
        // weighed its bundle's water (ten strands') would move further than they.
        assert!(dry_gap > 1e-4, "{backend:?}: the water's weight shows ({dry_gap} m)");
        assert!(
            wet_gap < 1e-4 && wet_gap < 1e-3 * dry_gap,
            "{backend:?}: soaked guides {wet_gap} m from the same strands simulated with all"
        );
    }
}

/// Lowering the simulated fraction and raising it again moves the water with the hair: the
/// total held is unchanged by each change, the ledger balances, and the groom shows the
/// wetness it had, everywhere (the guides a higher fraction adds take their share of their
/// old guides' water; those a lower one drops give theirs to the guides their strands follow).
#[test]
fn a_change_of_the_simulated_fraction_moves_the_water_with_the_hair() {
    let _serial = serial();
    let g = paper_scene(1000, 6).unwrap();
    for backend in backends() {
        let mut sim = Simulation::new(
            &g,
            params(
                backend,
                Guides {
                    choice: GuideChoice::Spread(1000),
                    ..Guides::ALL
                },
            ),
        )
        .unwrap();
        sim.soak(0.5).unwrap();
        sim.step(DT).unwrap();
        let spread = |w: &[f32]| w.iter().fold((f32::MAX, f32::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        let before = spread(&wetness(&mut sim));
        for f in [0.25, 1.0, 0.1] {
            let h0 = held(&sim);
            sim.set_guide_fraction(f).unwrap();
            assert_eq!(
                held(&sim),
                h0,
                "{backend:?}: the change to {f} moved the water, and only moved it"
            );
            for _ in 0..20 {
                sim.step(DT).unwrap();
            }
            let (lo, hi) = spread(&wetness(&mut sim));
            eprintln!("{backend:?}: {f} simulated: wetness {lo}..{hi} (before any change {before:?})");
            assert!(
                lo > 0.49 && hi < 0.51,
                "{backend:?}: at {f} the groom shows wetness {lo}..{hi}, soaked to 0.5"
            );
        }
    }
}

/// A guide draws water from a drop for its bundle's hair: drops scattered through the hair
/// soak in about as fast with a tenth of the strands simulated as with all of them (within a
/// third: a bundle's hair is where its followers are, not where the drop is; measured 0.242
/// against 0.195 in a frame), where a guide asking for its own strand alone would take about
/// a tenth as much (each drop meets a tenth of the points it meets with every strand
/// simulated).
#[test]
fn a_guide_draws_a_drop_in_for_its_bundle() {
    let _serial = serial();
    // The paper scene's 10,000 strands: dense enough that a drop reaches several strands.
    let g = paper_scene(10_000, 6).unwrap();
    let drops = wethair::scenes::on_hair(g.positions(), 300, &mut wethair::scenes::Lcg(5));
    for backend in backends() {
        let mut taken = Vec::new();
        for guides in [Guides::ALL, Guides::every_nth(10)] {
            let mut p = params(backend, guides);
            p.gravity = glam::Vec3::ZERO; // the drops stay where they are put
            p.held_water.flow_mobility = 0.0;
            p.water.particle_mass = 1.0e-5; // 10 mg: far below what the points they meet hold
                                            // A tenth of the default rate: a frame takes a part of each drop, in proportion to
                                            // the hair that reaches it, not all of it.
            p.held_water.absorb_rate = 2.0;
            let mut sim = Simulation::new(&g, p).unwrap();
            sim.add_water(&drops, &[]).unwrap();
            sim.step(DT).unwrap();
            let l = sim.water_ledger().unwrap();
            assert!(l.balanced(), "{l:?}");
            taken.push(l.held as f64 / l.added as f64);
        }
        eprintln!(
            "{backend:?}: drops soaked in one frame: {:.3} of their water with every strand simulated, {:.3} with a tenth",
            taken[0], taken[1]
        );
        assert!(taken[0] > 0.05, "{backend:?}: the drops soak in: {taken:?}");
        assert!(
            taken[1] > 0.67 * taken[0] && taken[1] < 1.5 * taken[0],
            "{backend:?}: a tenth simulated soaked {} of the drops in a frame, all {}",
            taken[1],
            taken[0]
        );
    }
}

/// Eq. 2's reaction in a guide groom: a guide pulls a drop back with its bundle's hair, as
/// the strands it stands for would. Eight places, each with ten strands one on another, and
/// a drop beside each (no gravity, the paper model): with one of the ten simulated per place
/// (its bundle is ten), the drops move as they do with all ten simulated (the reactions'
/// sums rounded in another order; the paper's drops orbit through the hair chaotically, some
/// flung out within a second, so the gap is read at a sixth of a second, before rounding has
/// grown: under 0.1 mm; measured 5.9 µm on the CPU, 17 µm on the GPU), each still on its
/// strand. Pulled back by one strand's hair, as before, they were 21 mm apart by then.
#[test]
fn a_guide_pulls_a_drop_with_its_bundle_s_hair() {
    let _serial = serial();
    // Eight places 5 cm apart, each with ten strands of 6 points hanging straight down, one
    // on another (strands 10p..10p+9: every 10th strand is the first of a place).
    let (places, per, points, seg) = (8usize, 10usize, 6usize, 0.005f32);
    let place = |p: usize| glam::Vec3::new(0.05 * (p % 4) as f32, 0.0, 0.05 * (p / 4) as f32);
    let mut pos = Vec::new();
    for p in 0..places {
        for _ in 0..per {
            pos.extend((0..points).map(|i| place(p) - glam::Vec3::Y * (seg * i as f32)));
        }
    }
    let g = wethair::groom::Groom::new(pos, &vec![points as u32; places * per], None, None, 1.0e-3).unwrap();
    // Each drop 3.5 to 3.85 mm to the side of its place's third point.
    let drops: Vec<glam::Vec3> = (0..places)
        .map(|p| place(p) + glam::Vec3::new(0.0035 + 0.00005 * p as f32, -2.0 * seg, 0.0))
        .collect();
    // The drops by place (the simulation returns them in its own order), each checked to lie
    // within eq. 2's reach (8 mm) of its place's strand.
    let by_place = |x: &[glam::Vec3], what: &str| -> Vec<glam::Vec3> {
        let off = |d: &glam::Vec3, p: usize| glam::Vec2::new(d.x - place(p).x, d.z - place(p).z).length();
        let mut out = vec![None; places];
        for d in x {
            let p = (0..places).min_by(|&a, &b| off(d, a).total_cmp(&off(d, b))).unwrap();
            assert!(
                off(d, p) < 0.008 && (0.0..=seg * points as f32).contains(&-d.y),
                "{what}: a drop at {d:?} is {} m off its strand",
                off(d, p)
            );
            assert!(out[p].replace(*d).is_none(), "{what}: two drops at place {p}");
        }
        out.iter()
            .enumerate()
            .map(|(p, d)| d.unwrap_or_else(|| panic!("{what}: no drop at place {p}: {x:?}")))
            .collect()
    };
    for backend in backends() {
        let mut early = Vec::new();
        for guides in [
            Guides::ALL,
            Guides {
                per_follower: 1,
                ..Guides::every_nth(per as u32)
            },
        ] {
            let what = format!("{backend:?}, {:?}", guides.choice);
            let p = SimParams {
                backend,
                guides,
                colliders: Vec::new(),
                gravity: glam::Vec3::ZERO,
                ..SimParams::paper()
            };
            let mut sim = Simulation::new(&g, p).unwrap();
            sim.add_water(&drops, &[]).unwrap();
            for _ in 0..10 {
                sim.step(DT).unwrap();
            }
            early.push(by_place(&sim.water().unwrap().0, &what));
        }
        let moved = early[0]
            .iter()
            .zip(&drops)
            .map(|(a, b)| a.distance(*b))
            .fold(f32::MAX, f32::min);
        let gap = early[0]
            .iter()
            .zip(&early[1])
            .map(|(a, b)| a.distance(*b))
            .fold(0.0f32, f32::max);
        eprintln!(
            "{backend:?}: after 10 frames every drop moved at least {moved:.2e} m; a tenth simulated against all: {gap:.2e} m apart at most"
        );
        assert!(moved > 1.0e-3, "{backend:?}: the drops moved {moved} m");
        assert!(gap < 1.0e-4, "{backend:?}: the drops {gap} m apart");
    }
}

/// Guides under a shower, their fraction lowered and raised while the water flows, drips and
/// soaks in: every vertex and the ledger repeat bit for bit on 1 and 4 CPU threads, and run
/// after run on the GPU.
#[test]
fn wet_guides_through_changes_of_fraction_repeat_bit_for_bit() {
    let _serial = serial();
    let g = paper_scene(2000, 6).unwrap();
    let run = |backend: Backend, threads: u32| {
        let mut p = params(backend, Guides::every_nth(4));
        p.threads = threads;
        p.held_water.bridge_tension = 2.0 * 0.072; // bridges too
        let mut sim = Simulation::new(&g, p).unwrap();
        let mut rng = wethair::scenes::Lcg(11);
        let mut out = Vec::new();
        for f in 0..45u32 {
            let drops = wethair::scenes::on_hair(g.positions(), 20, &mut rng);
            sim.add_water(&drops, &[]).unwrap();
            if f == 10 {
                sim.soak(1.5).unwrap();
            }
            match f {
                15 => sim.set_guide_fraction(0.3).unwrap(),
                30 => sim.set_guide_fraction(1.0).unwrap(),
                _ => {}
            }
            sim.step(DT).unwrap();
        }
        out.extend(wetness(&mut sim).iter().map(|w| w.to_bits()));
        let mut v = vec![0.0; sim.vertex_count() * sim.attributes().stride()];
        sim.write_vertices(&mut v).unwrap();
        out.extend(v.iter().map(|x| x.to_bits()));
        let l = sim.water_ledger().unwrap();
        assert!(l.balanced(), "{backend:?}: {l:?}");
        assert!(
            l.held > 0 && l.in_particles > 0,
            "{backend:?}: water in the hair and in drops: {l:?}"
        );
        (out, l)
    };
    let (one, l1) = run(Backend::CPU, 1);
    let (four, l4) = run(Backend::CPU, 4);
    assert_eq!(l1, l4, "the CPU's ledger on 1 and 4 threads");
    assert!(one == four, "the CPU's vertices on 1 and 4 threads");
    if backends().contains(&Backend::GPU) {
        let (a, la) = run(Backend::GPU, 0);
        let (b, lb) = run(Backend::GPU, 0);
        assert_eq!(la, lb, "the GPU's ledger run after run");
        assert!(a == b, "the GPU's vertices run after run");
        eprintln!("wet guides: CPU ledger {l1:?}; GPU {la:?}");
    }
}
