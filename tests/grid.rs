//! The grid's neighbour query equals brute force, for points inside and far outside its box.

use glam::Vec3;
use wethair::physics::grid::{Grid, MAX_CELLS};
use wethair::scenes::Lcg;

fn cloud(rng: &mut Lcg, n: usize, lo: Vec3, hi: Vec3) -> Vec<Vec3> {
    (0..n)
        .map(|_| lo + (hi - lo) * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
        .collect()
}

fn check(points: &[Vec3], queries: &[Vec3], r: f32, cell: f32) {
    let mut grid = Grid::new(points.len(), cell);
    grid.build(points);
    for q in queries {
        let mut found: Vec<u32> = vec![];
        grid.for_each_candidate(*q, r, |i| {
            if (points[i as usize] - *q).length_squared() <= r * r {
                found.push(i);
            }
        });
        let n = found.len();
        found.sort_unstable();
        found.dedup();
        assert_eq!(found.len(), n, "a candidate was visited twice");
        let brute: Vec<u32> = (0..points.len() as u32)
            .filter(|&i| (points[i as usize] - *q).length_squared() <= r * r)
            .collect();
        assert_eq!(found, brute, "query at {q:?}");
        if !brute.is_empty() {
            assert!(
                grid.may_have_near(*q, r),
                "prefilter rejected {q:?} with {} neighbours",
                brute.len()
            );
        }
    }
}

#[test]
fn grid_query_equals_brute_force_on_random_clouds() {
    let mut rng = Lcg(99);
    for (n, r) in [(1usize, 0.01f32), (50, 0.02), (2000, 0.01), (5000, 0.005)] {
        let pts = cloud(&mut rng, n, Vec3::splat(-0.1), Vec3::splat(0.1));
        // Queries inside, on the border, and far outside the points' box.
        let mut queries = cloud(&mut rng, 300, Vec3::splat(-0.15), Vec3::splat(0.15));
        queries.extend([
            Vec3::splat(1e3),
            Vec3::splat(-1e3),
            Vec3::new(0.1 + r * 0.5, 0.0, 0.0),
            Vec3::new(f32::MAX, 0.0, 0.0),
        ]);
        check(&pts, &queries, r, r);
        check(&pts, &queries, r, 2.0 * r);
    }
}

#[test]
fn grid_handles_far_apart_points_by_growing_cells() {
    // Two clusters 1 km apart would need ~10^15 cells of 1 cm: the grid grows its cells
    // instead, and every query stays exact.
    let mut rng = Lcg(5);
    let mut pts = cloud(&mut rng, 200, Vec3::ZERO, Vec3::splat(0.05));
    pts.extend(cloud(&mut rng, 200, Vec3::splat(1000.0), Vec3::splat(1000.05)));
    let queries: Vec<Vec3> = pts.iter().step_by(7).map(|p| *p + Vec3::splat(0.003)).collect();
    check(&pts, &queries, 0.01, 0.01);
    let mut g = Grid::new(pts.len(), 0.01);
    g.build(&pts);
    assert!(g.dims().as_i64vec3().element_product() <= MAX_CELLS as i64);
    assert!(g.cell() > 0.01);
}

/// The prefilter stays tight when the particles spread wide (rain over a head): the counting
/// sort's cells grow with the box (here to several times the reach), but the prefilter reads
/// a finer grid of cells of the reach, so it lets through a few times the points that truly
/// have a neighbour, not the whole neighbourhood of the grown cells (which passed ~100 times).
/// How many `queries` the prefilter of `g` (built over `pts`) passes, and how many truly have
/// a point within `r`; fails on any query with a neighbour that the prefilter rejects.
fn prefilter_counts(g: &Grid, pts: &[Vec3], queries: &[Vec3], r: f32) -> (usize, usize) {
    let (mut pass, mut near) = (0usize, 0usize);
    for q in queries {
        let has = pts.iter().any(|p| (*p - *q).length_squared() <= r * r);
        let may = g.may_have_near(*q, r);
        assert!(may || !has, "prefilter rejected {q} with a neighbour");
        pass += may as usize;
        near += has as usize;
    }
    (pass, near)
}

#[test]
fn prefilter_stays_tight_when_particles_spread_wide() {
    let mut rng = Lcg(21);
    let r = 0.008;
    let pts = cloud(&mut rng, 2000, Vec3::ZERO, Vec3::ONE);
    let queries = cloud(&mut rng, 200_000, Vec3::ZERO, Vec3::ONE);
    let mut g = Grid::new(pts.len(), r);
    g.build(&pts);
    assert!(g.cell() > 2.0 * r, "the sort's cells grew: {}", g.cell());
    let (pass, near) = prefilter_counts(&g, &pts, &queries, r);
    // 27 cells of side r around each particle hold 27 / (4/3 pi) = 6.4 times its sphere.
    assert!(near > 100, "too few queries with a neighbour to judge: {near}");
    assert!(
        pass <= 8 * near,
        "{pass} of {} queries pass, {near} have a neighbour",
        queries.len()
    );
}

/// Dense water (blobs of hundreds of drops within a centimetre, as a shower leaves in the
/// hair) is where the prefilter marks runs of drops as one box: it still passes every query
/// with a drop within reach, including queries exactly `r` from a drop along each axis, and
/// stays about as tight.
#[test]
fn prefilter_never_rejects_a_neighbour_of_dense_water() {
    let mut rng = Lcg(8);
    let r = 0.008;
    let mut pts = vec![];
    for _ in 0..60 {
        let c = cloud(&mut rng, 1, Vec3::ZERO, Vec3::splat(0.3))[0];
        pts.extend(cloud(&mut rng, 300, c - 0.005, c + 0.005));
    }
    // Built twice, as the step does: the second build takes the points in the first's order.
    let mut g = Grid::new(pts.len(), r);
    g.build(&pts);
    let pts: Vec<Vec3> = g.sorted().iter().map(|&j| pts[j as usize]).collect();
    g.build(&pts);
    let mut queries = cloud(&mut rng, 100_000, Vec3::splat(-0.01), Vec3::splat(0.31));
    for p in pts.iter().step_by(7) {
        for d in [Vec3::X, Vec3::Y, Vec3::Z] {
            queries.extend([*p + d * r, *p - d * r]);
        }
    }
    let (pass, near) = prefilter_counts(&g, &pts, &queries, r);
    assert!(near > 5_000, "too few queries with a neighbour to judge: {near}");
    assert!(
        pass <= 4 * near,
        "{pass} of {} queries pass, {near} have a neighbour",
        queries.len()
    );
}

#[test]
fn grid_counting_sort_counts_every_point_once() {
    let mut rng = Lcg(11);
    let pts = cloud(&mut rng, 3000, Vec3::splat(-0.2), Vec3::splat(0.2));
    let mut g = Grid::new(pts.len(), 0.016);
    g.build(&pts);
    assert_eq!(g.cell_counts().iter().sum::<u32>() as usize, pts.len());
    let mut seen = g.sorted().to_vec();
    seen.sort_unstable();
    assert_eq!(seen, (0..pts.len() as u32).collect::<Vec<_>>());
}

/// Queries of radius exactly one cell from points on cell boundaries: rounding can put a face
/// of the query cube just past a boundary (4 columns a side); the walk must still cover every
/// point within r (found by the clumping measure on GPU tips).
#[test]
fn queries_of_one_cell_radius_from_cell_boundaries() {
    let pts: Vec<glam::Vec3> = (0..12)
        .flat_map(|i| (0..12).map(move |j| glam::Vec3::new(i as f32 * 0.1, j as f32 * 0.1, (i + j) as f32 * 0.05)))
        .collect();
    let mut grid = wethair::physics::grid::Grid::new(pts.len(), 0.1);
    grid.build(&pts);
    let r = grid.cell();
    for &p in &pts {
        for q in [p, p + glam::Vec3::splat(1e-7), p - glam::Vec3::splat(1e-7)] {
            let mut found = vec![false; pts.len()];
            grid.for_each_candidate(q, r, |j| found[j as usize] = true);
            for (j, &x) in pts.iter().enumerate() {
                if (x - q).length() <= r {
                    assert!(found[j], "point {j} within r of {q} was not visited");
                }
            }
        }
    }
}

/// Any finite box works (issue 13, item 1): points up to FLT_MAX apart, 2e7 m away, and a
/// cell of 1e-6 m over a metre wide cloud build a grid within the cell budget whose query
/// still equals brute force.
#[test]
fn grid_handles_any_finite_extent() {
    let mut rng = Lcg(5);
    let near = cloud(&mut rng, 300, Vec3::splat(-0.05), Vec3::splat(0.05));
    let qs = cloud(&mut rng, 50, Vec3::splat(-0.06), Vec3::splat(0.06));
    for far in [
        vec![Vec3::new(f32::MAX, 0.0, 0.0), Vec3::new(-f32::MAX, -f32::MAX, f32::MAX)],
        vec![Vec3::new(2e7, 0.0, 0.0)],
        vec![Vec3::splat(1e30), Vec3::splat(-1e30)],
    ] {
        let pts: Vec<Vec3> = near.iter().copied().chain(far).collect();
        let mut grid = Grid::new(pts.len(), 0.01);
        grid.build(&pts);
        assert!(grid.dims().as_i64vec3().element_product() <= MAX_CELLS as i64);
        check(&pts, &qs, 0.01, 0.01);
    }
    let wide = cloud(&mut rng, 1000, Vec3::splat(-0.5), Vec3::splat(0.5));
    check(&wide, &qs, 1e-6, 1e-6);
}

/// The hashed grid (the hair grid of the liquid bridges) finds exactly the brute-force
/// neighbours, each once, for clouds small and wide (where the box grid would grow its cells),
/// queries far away, at negative coordinates, and with radius up to its cell.
#[test]
fn hash_grid_query_equals_brute_force() {
    use wethair::physics::hash_grid::HashGrid;
    let mut rng = Lcg(7);
    for (n, r, half) in [
        (1usize, 0.004f32, 0.01f32),
        (300, 0.004, 0.01),
        (5000, 0.00375, 0.5),
        (20000, 0.002, 0.05),
    ] {
        let pts = cloud(&mut rng, n, Vec3::splat(-half), Vec3::splat(half));
        let mut queries: Vec<Vec3> = pts.iter().step_by((n / 200).max(1)).copied().collect();
        queries.extend(cloud(&mut rng, 100, Vec3::splat(-half), Vec3::splat(half)));
        queries.extend([
            Vec3::splat(1e3),
            Vec3::splat(-1e3),
            Vec3::new(f32::MAX, 0.0, 0.0),
            Vec3::NAN,
        ]);
        for (cell, parallel) in [(r, false), (1.5 * r, false), (2.0 * r, false), (2.0 * r, true)] {
            let mut grid = HashGrid::new(cell);
            grid.build(&pts, parallel);
            for q in &queries {
                let mut found = vec![];
                grid.for_each_near(*q, r, |i, d2| {
                    assert_eq!(d2, (pts[i as usize] - *q).length_squared());
                    found.push(i);
                });
                let visits = found.len();
                found.sort_unstable();
                found.dedup();
                assert_eq!(found.len(), visits, "a candidate was visited twice");
                let brute: Vec<u32> = (0..n as u32)
                    .filter(|&i| (pts[i as usize] - *q).length_squared() < r * r)
                    .collect();
                assert_eq!(found, brute, "query at {q:?}, n {n}, cell {cell}");
            }
        }
    }
}

/// The stats' clumping measures, run as jobs on the simulation's pool, are the measures'
/// functions' values to the bit, on one thread and on three.
#[test]
fn stats_clumping_is_the_measures_on_any_thread_count() {
    use wethair::physics::clumping::{mean_nearest_along_strands, mean_nearest_tip_distance};
    use wethair::{Backend, SimParams, Simulation};
    let _s = crate::common::serial();
    let groom = wethair::groom::paper_scene(2_000, 6).expect("groom");
    let mut first: Vec<u32> = (0..groom.strand_count())
        .map(|s| groom.strand_range(s).start as u32)
        .collect();
    first.push(groom.positions().len() as u32);
    let mut seen = Vec::new();
    for threads in [1, 3] {
        let params = SimParams {
            backend: Backend::CPU,
            threads,
            ..SimParams::paper_scene_with_head()
        };
        let mut sim = Simulation::new(&groom, params).expect("sim");
        let water = wethair::scenes::on_hair(groom.positions(), 200, &mut Lcg(4));
        sim.add_water(&water, &[]).expect("water");
        for _ in 0..20 {
            sim.step(1.0 / 60.0).expect("step");
        }
        let st = sim.stats();
        let x = sim.positions();
        assert_eq!(st.clumping.to_bits(), mean_nearest_tip_distance(&sim.tips()).to_bits());
        assert_eq!(
            st.clumping_along.to_bits(),
            mean_nearest_along_strands(&x, &first).to_bits()
        );
        seen.push((st.clumping.to_bits(), st.clumping_along.to_bits()));
    }
    assert_eq!(seen[0], seen[1], "one thread against three");
}

/// The step's count of adhesion pairs (`Stats::adhesion_pairs`, what the benches divide the
/// water's cost by) equals brute force: hair points set at least 2 `r_max` apart, so a
/// particle reaches at most one point of any row, and one substep, so the hair and the
/// particles are where they were placed when the pairs are found. The same count on 1 and 3
/// threads; none with the particles out of reach, and none after a reset.
#[test]
fn adhesion_pairs_counted_by_the_step_equal_brute_force() {
    use wethair::{groom::Groom, Backend, SimParams, Simulation};
    let base = SimParams {
        backend: Backend::CPU,
        ..SimParams::paper()
    };
    let r = base.water.r_max;
    // 12 strands of 5 points on a 4 × 3 lattice, 2.5 r_max apart across, 3 r_max along.
    let (strands, points) = (12usize, 5usize);
    let hair: Vec<Vec3> = (0..strands)
        .flat_map(|s| {
            let (x, y) = ((s % 4) as f32 * 2.5 * r, (s / 4) as f32 * 2.5 * r);
            (0..points).map(move |i| Vec3::new(x, y, -3.0 * r * i as f32))
        })
        .collect();
    let groom = Groom::new(hair.clone(), &vec![points as u32; strands], None, None, 1e-3).unwrap();
    let mut rng = Lcg(7);
    let drops = cloud(
        &mut rng,
        200,
        Vec3::new(-r, -r, -13.0 * r),
        Vec3::new(8.5 * r, 6.0 * r, r),
    );
    let brute = drops
        .iter()
        .map(|p| hair.iter().filter(|&&x| (*p - x).length_squared() <= r * r).count() as u64)
        .sum::<u64>();
    assert!(brute > 20, "the drops reach the hair: {brute} pairs");
    for (threads, shift) in [(1u32, 0.0f32), (3, 0.0), (1, 1.0)] {
        let mut p = base.clone();
        (p.threads, p.substeps, p.gravity) = (threads, 1, Vec3::ZERO);
        let mut sim = Simulation::new(&groom, p).unwrap();
        let placed: Vec<Vec3> = drops.iter().map(|d| *d + Vec3::X * shift).collect();
        sim.add_water(&placed, &[]).unwrap();
        sim.step(1.0 / 240.0).unwrap();
        let want = if shift == 0.0 { brute } else { 0 };
        assert_eq!(
            sim.counters().adhesion_pairs,
            want,
            "{threads} threads, drops moved {shift} m"
        );
        sim.reset().unwrap();
        assert_eq!(
            sim.counters().adhesion_pairs,
            0,
            "a reset forgets the last step's pairs"
        );
    }
}
