//! The full wet model on a real long-strand groom (issue 14's behaviour on something other than
//! the paper scene): the TressFX ponytail in metres with the loader's 1 g per metre and the
//! default material springs, soaked, against a dry twin. Soaked hair hangs lower, drops fall
//! from the tips, the strands stay bundled while wet and let go as they dry.

use glam::Vec3;
use wethair::groom::{load_file_with, Groom, LoadOptions, UpAxis};
use wethair::scenes::{on_hair, Lcg};
use wethair::{Backend, HeldWater, SimParams, Simulation};

use crate::common::{backends, serial};

const DT: f32 = 1.0 / 60.0;

/// The ponytail (517 strands of 16 points, centimetres and y up in the file) in metres, z up,
/// with the loader's default mass (1 g per metre of strand).
fn ponytail() -> Groom {
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ponytail_back.tfx"));
    let opt = LoadOptions {
        scale: 0.01,
        up_axis: UpAxis::Y_TO_Z,
        ..Default::default()
    };
    load_file_with(path, &opt).unwrap()
}

/// Mean height of the strands' last points, m.
fn mean_tip_z(sim: &Simulation, groom: &Groom) -> f32 {
    let x = sim.positions();
    let ends: Vec<usize> = (0..groom.strand_count())
        .map(|s| groom.strand_range(s).end - 1)
        .collect();
    ends.iter().map(|&i| x[i].z).sum::<f32>() / ends.len() as f32
}

/// The longest segment of `groom` at `x` over its rest length, minus 1 (either way: a segment
/// squeezed by as much counts alike).
fn max_strain(groom: &Groom, x: &[Vec3]) -> f32 {
    let rest = groom.positions();
    let mut worst = 0.0f32;
    for s in 0..groom.strand_count() {
        for i in groom.strand_range(s).start..groom.strand_range(s).end - 1 {
            let l0 = rest[i + 1].distance(rest[i]);
            worst = worst.max((x[i + 1].distance(x[i]) / l0 - 1.0).abs());
        }
    }
    worst
}

/// Eq. 2 on a real groom with the default parameters (the paper's model): the ponytail at the
/// loader's 1 g/m, 1,000 drops of 1 g placed in it. Its points weigh 10 mg against the paper
/// scene's 1 g, and one drop's pull, even per 2 cm of hair, is 4.6 times what a 240 Hz
/// substep follows (`h² K / m`; docs/METHOD.md §2, the pull's stability limit). Before the
/// limit its points rang in the drops' wells and tore their segments: the longest was 68 %
/// past its rest length at frame 2 and 113 % at frame 10, then 10-35 % once most drops had
/// fallen through, against 0.8 % dry (measured 2026-11-29 every second frame). With the
/// limit the hair rings no more: the kilogram of water dragging through it (125 times the
/// hair's own mass) stretches the longest segment by 13.6 % at frame 9, less than eq. 2's own
/// load does where the limit hardly acts (30.5 % at frame 21 at 64 substeps, 25.8 % at 16;
/// measured 2026-12-01). When the limit counted each pair at the steepest slope it held the
/// pulls to a third and less, and the drops slid through the hair at 2.5 %. The bound is
/// 20 %. The drops still move the hair.
#[test]
fn a_real_groom_under_a_thousand_drops_keeps_its_length() {
    let _g = serial();
    let groom = ponytail();
    for backend in backends() {
        let params = SimParams {
            backend,
            ..SimParams::default()
        };
        let mut dry = Simulation::new(&groom, params.clone()).unwrap();
        let mut wet = Simulation::new(&groom, params).unwrap();
        let drops = on_hair(groom.positions(), 1000, &mut Lcg(7));
        wet.add_water(&drops, &[]).unwrap();
        let mut worst = 0.0f32;
        for _ in 0..60 {
            dry.step(DT).unwrap();
            wet.step(DT).unwrap();
            worst = worst.max(max_strain(&groom, &wet.positions()));
        }
        let (a, b) = (dry.positions(), wet.positions());
        let moved = a.iter().zip(&b).map(|(p, q)| p.distance(*q)).sum::<f32>() / a.len() as f32;
        println!("{backend:?}: longest stretch {worst}, mean distance from the dry twin {moved} m");
        assert!(worst < 0.2, "{backend:?}: a segment stretched by {worst}");
        assert!(
            moved > 1.0e-3,
            "{backend:?}: the drops moved the hair by {moved} m on average"
        );
    }
}

/// The hair side of eq. 2's stability limit holds a light point's pulls to what a substep
/// follows, and no further: the ponytail (10 mg points) with 1,000 drops of 10 mg placed in
/// it clumps at the default 4 substeps about as it does at 64, where the limit hardly acts.
/// The limit sums each pair's own stiffness at its distance (`adhesion::pair_stiffness`);
/// with the profile's steepest slope for every pair, as it first did, the tips' clumping
/// after a second was 8.9 mm at 4 substeps against 4.6 at 64 (94 % off); now 5.3 against
/// 4.5 (measured 2026-12-01). The drops are light enough to stay in the hair at any substep.
#[test]
fn a_real_groom_clumps_at_4_substeps_as_at_64() {
    let _serial = serial();
    let groom = ponytail();
    let clumping = |substeps: u32| {
        let params = SimParams {
            backend: Backend::CPU,
            substeps,
            water: wethair::WaterParams {
                particle_mass: 1.0e-5,
                ..SimParams::default().water
            },
            ..SimParams::default()
        };
        let mut sim = Simulation::new(&groom, params).unwrap();
        sim.add_water(&on_hair(groom.positions(), 1000, &mut Lcg(7)), &[])
            .unwrap();
        for _ in 0..60 {
            sim.step(DT).unwrap();
        }
        assert_eq!(sim.stats().particles, 1000, "{substeps} substeps: drops left the hair");
        sim.stats().clumping
    };
    let (coarse, fine) = (clumping(4), clumping(64));
    println!("tips' clumping: {coarse} m at 4 substeps, {fine} m at 64");
    assert!(
        (coarse / fine - 1.0).abs() < 0.3,
        "4 substeps clump the tips to {coarse} m against {fine} m at 64"
    );
}

#[test]
fn a_soaked_ponytail_hangs_lower_drips_from_its_tips_and_lets_go_as_it_dries() {
    let _serial = serial();
    let groom = ponytail();
    let base = SimParams {
        backend: Backend::CPU,
        ..SimParams::default()
    };
    let wet_params = SimParams {
        held_water: HeldWater {
            dry_time: 1.0,
            ..HeldWater::ON
        },
        ..base.clone()
    };
    let mut dry = Simulation::new(&groom, base).unwrap();
    let mut wet = Simulation::new(&groom, wet_params).unwrap();
    // Settle under gravity, then soak to twice what the hair holds against gravity, as out of
    // a bath: the excess runs to the tips and drips.
    for _ in 0..60 {
        dry.step(DT).unwrap();
        wet.step(DT).unwrap();
    }
    wet.soak(2.0).unwrap();
    let tip_rows: Vec<usize> = (0..groom.strand_count())
        .map(|s| groom.strand_range(s).end - 1)
        .collect();
    let r_max = wet.params().water.r_max;
    let (mut ratios, mut sags) = (Vec::new(), Vec::new());
    // Drops made in the first second, and how many of them r_max below a tip.
    let (mut made, mut from_tips, mut seen) = (0usize, 0usize, 0usize);
    for f in 1..=480 {
        let tips: Vec<Vec3> = {
            let x = wet.positions();
            tip_rows.iter().map(|&i| x[i]).collect()
        };
        dry.step(DT).unwrap();
        wet.step(DT).unwrap();
        let (drops, _) = wet.water().unwrap();
        // New drops are appended (the drip pass runs after the cull): those past the count
        // the last frame left.
        if f <= 60 && drops.len() > seen {
            let new = &drops[seen..];
            made += new.len();
            let below_a_tip = |d: &Vec3| tips.iter().any(|t| t.distance(*d) < 2.0 * r_max && d.z < t.z);
            from_tips += new.iter().filter(|d| below_a_tip(d)).count();
        }
        seen = drops.len();
        let t = f as f32 * DT;
        if f % 15 == 0 {
            ratios.push((t, wet.stats().clumping_along / dry.stats().clumping_along));
            sags.push((t, mean_tip_z(&dry, &groom) - mean_tip_z(&wet, &groom)));
        }
    }
    // Soaked hair is heavier and limper: its tips hang lower than the dry twin's while wet.
    let wet_sag: Vec<f32> = sags
        .iter()
        .filter(|(t, _)| (0.5..=3.0).contains(t))
        .map(|p| p.1)
        .collect();
    let mean_sag = wet_sag.iter().sum::<f32>() / wet_sag.len() as f32;
    assert!(
        mean_sag > 1e-4 && wet_sag.iter().all(|&d| d > 0.0),
        "tips lower by {sags:?}"
    );
    // It drips, and mostly from the tips: a drop appears within r_max (plus what it falls in
    // a frame) below the point it left, and water leaves only where it cannot run on, the
    // tips and the low points of the strands that curl (that drops then fall freely is
    // tests/wet_model.rs's). Measured: 1,615 of the first second's 2,253 drops below a tip
    // (706 of 1,060 before 0.7.0, when the water ran half as fast on these 1 cm segments).
    println!("{from_tips} of the first second's {made} drops below a tip");
    assert!(made > 100, "the soaked ponytail drips: {made} drops");
    assert!(2 * from_tips > made, "{from_tips} of {made} drops from the tips");
    // Bundled while wet (measurably; see the closing note of issue 14 on light hair), within
    // 10% of dry again once dried.
    let wet_ratio = ratios
        .iter()
        .filter(|(t, _)| (0.5..=2.0).contains(t))
        .map(|p| p.1)
        .fold(f32::INFINITY, f32::min);
    assert!(wet_ratio < 0.97, "clumping while wet {ratios:?}");
    let (t, last) = *ratios.last().unwrap();
    assert!(last >= 0.9, "let go by {t:.2} s: {ratios:?}");
    assert!(wet.water_ledger().unwrap().balanced());
}
