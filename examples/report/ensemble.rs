//! Honest error on chaotic scenes. Where water clumps the hair, moving one droplet by 1e-7 m
//! moves the hair by far more within a second (a strand caught by a droplet in one run and not
//! in another), so a pointwise error below that spread cannot rank integrators. Instead, an
//! ensemble of reference runs whose hair and water are nudged by [`NUDGE`] sets a band for each
//! statistic the eye sees (how clumped, how much energy, where each strand hangs), and an
//! integrator's run whose statistics lie in the band counts as converged.

use glam::{DVec3, Vec3};
use wethair::groom::Groom;
use wethair::physics::clumping::mean_nearest_along_strands;
use wethair::scenes::ReportScene;
use wethair::SimParams;

/// Size of each free point's nudge (hair point or water particle) in the ensemble's members, m.
pub const NUDGE: f64 = 1e-7;

/// The statistics of the hair at the end of a run.
#[derive(Clone, Debug)]
pub struct Statistics {
    /// Clumping: the mean nearest-other-strand distance along the strands, m.
    pub clumping: f64,
    /// Kinetic, spring and gravitational energy of hair and water, J.
    pub energy: f64,
    /// Each strand's centre of mass (its points' mean position), m.
    pub centres: Vec<DVec3>,
}

impl Statistics {
    /// The statistics of hair positions `x` (host order) of `sc`'s groom with `energy`.
    pub fn of(sc: &ReportScene, x: &[DVec3], energy: f64) -> Statistics {
        let g = &sc.groom;
        let xf: Vec<Vec3> = x.iter().map(|p| p.as_vec3()).collect();
        let first: Vec<u32> = (0..=g.strand_count())
            .map(|s| {
                if s == g.strand_count() {
                    x.len() as u32
                } else {
                    g.strand_range(s).start as u32
                }
            })
            .collect();
        let centres = (0..g.strand_count())
            .map(|s| {
                let r = g.strand_range(s);
                x[r.clone()].iter().sum::<DVec3>() / r.len() as f64
            })
            .collect();
        Statistics {
            clumping: mean_nearest_along_strands(&xf, &first) as f64,
            energy,
            centres,
        }
    }
}

/// The band the ensemble's members span.
pub struct Band {
    /// Least and greatest clumping of the members, m.
    pub clumping: (f64, f64),
    /// Least and greatest energy of the members, J.
    pub energy: (f64, f64),
    /// The members' mean centre of each strand, m.
    pub mean_centres: Vec<DVec3>,
    /// The greatest RMS distance (over strands) of a member's centres from the mean ones, m.
    pub centre_spread: f64,
    /// The members' typical distance from their mean centres: the root mean square over
    /// members of each one's RMS distance, m.
    pub centre_rms: f64,
    /// How many members the band was made of.
    pub members: usize,
}

/// An ensemble of one integrator's runs against the references' [`Band`]: how many runs lie
/// in the band, and whether the two ensembles' mean centres are further apart than their
/// spreads explain.
pub struct EnsembleVerdict {
    /// Runs that lie in the band (all three statistics), of [`EnsembleVerdict::runs`].
    pub in_band: usize,
    /// Runs that finished (did not diverge).
    pub runs: usize,
    /// Each run's strand centres' RMS distance from the references' mean: median, least and
    /// greatest, m.
    pub distance: (f64, f64, f64),
    /// The RMS distance (over strands) between this ensemble's mean centres and the
    /// references', m.
    pub means_apart: f64,
    /// What chance alone would set them apart: the standard error of the difference of two
    /// means, `sqrt(rms_ref² / n_ref + rms² / n)` with each ensemble's [`Band::centre_rms`], m.
    pub by_chance: f64,
}

/// Where one run's statistics fall against a [`Band`].
pub struct Verdict {
    pub clumping: bool,
    pub energy: bool,
    /// RMS distance of the run's strand centres from the ensemble's mean ones, m.
    pub centre_distance: f64,
    pub centres: bool,
}

impl Verdict {
    /// All three statistics inside the band.
    pub fn converged(&self) -> bool {
        self.clumping && self.energy && self.centres
    }
}

fn rms_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    (a.iter().zip(b).map(|(p, q)| p.distance_squared(*q)).sum::<f64>() / a.len() as f64).sqrt()
}

impl Band {
    /// The band of `members` (at least two).
    pub fn new(members: &[Statistics]) -> Band {
        let range = |f: &dyn Fn(&Statistics) -> f64| {
            members
                .iter()
                .map(f)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)))
        };
        let n = members.len() as f64;
        let mean_centres: Vec<DVec3> = (0..members[0].centres.len())
            .map(|s| members.iter().map(|m| m.centres[s]).sum::<DVec3>() / n)
            .collect();
        let distances: Vec<f64> = members
            .iter()
            .map(|m| rms_distance(&m.centres, &mean_centres))
            .collect();
        Band {
            clumping: range(&|m| m.clumping),
            energy: range(&|m| m.energy),
            mean_centres,
            centre_spread: distances.iter().copied().fold(0.0, f64::max),
            centre_rms: (distances.iter().map(|d| d * d).sum::<f64>() / n).sqrt(),
            members: members.len(),
        }
    }

    /// Where an ensemble of one integrator's runs falls (`None`: the run diverged); `None`
    /// when fewer than two runs finished.
    pub fn judge_ensemble(&self, runs: &[Option<Statistics>]) -> Option<EnsembleVerdict> {
        let done: Vec<Statistics> = runs.iter().flatten().cloned().collect();
        if done.len() < 2 {
            return None;
        }
        let own = Band::new(&done);
        let mut distance: Vec<f64> = done
            .iter()
            .map(|s| rms_distance(&s.centres, &self.mean_centres))
            .collect();
        distance.sort_by(f64::total_cmp);
        let (n_ref, n) = (self.members as f64, own.members as f64);
        Some(EnsembleVerdict {
            in_band: done.iter().filter(|s| self.judge(s).converged()).count(),
            runs: done.len(),
            distance: (distance[distance.len() / 2], distance[0], distance[distance.len() - 1]),
            means_apart: rms_distance(&own.mean_centres, &self.mean_centres),
            by_chance: (self.centre_rms.powi(2) / n_ref + own.centre_rms.powi(2) / n).sqrt(),
        })
    }

    /// Where `s` falls.
    pub fn judge(&self, s: &Statistics) -> Verdict {
        let inside = |(lo, hi): (f64, f64), v: f64| v >= lo && v <= hi;
        let centre_distance = rms_distance(&s.centres, &self.mean_centres);
        Verdict {
            clumping: inside(self.clumping, s.clumping),
            energy: inside(self.energy, s.energy),
            centre_distance,
            centres: centre_distance <= self.centre_spread,
        }
    }
}

/// A splitmix64 step: member `k`'s nudges are the same in every run of the report.
fn mix(z: u64) -> u64 {
    let z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A direction, uniform enough for a nudge, from `seed`.
fn direction(seed: u64) -> DVec3 {
    let u = |k: u64| (mix(seed.wrapping_mul(3).wrapping_add(k)) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
    let d = DVec3::new(u(0), u(1), u(2));
    if d.length_squared() > 1e-6 {
        d.normalize()
    } else {
        DVec3::X
    }
}

/// The nudge of free point `i` (hair points first, then water particles, as the reference
/// orders them) in member `k`.
fn nudge(k: usize, i: usize) -> DVec3 {
    NUDGE * direction(mix(k as u64 + 1) ^ i as u64)
}

/// The statistics at `t` of `members` references of `sc` (RK4 at step `h`), member `k`'s
/// every free hair point and every water particle moved by [`NUDGE`], each in its own
/// direction. The hair is nudged as well as the water: a judged run's own error (and its f32
/// rounding) reaches the hair points directly, not through the droplets, and the droplets
/// alone span a band 0.6x as wide on the wet patch.
pub fn run(sc: &ReportScene, members: usize, t: f64, h: f64) -> Vec<Statistics> {
    each_member(members, |k| {
        let mut r = sc.reference().moved(|i| nudge(k, i));
        r.run_to(t, h);
        Statistics::of(sc, r.hair_positions(), r.energy())
    })
}

/// The statistics after 1 s (60 frames) of `members` simulations of `sc` under `params`, each
/// nudged as the references' member of its number is (`None`: it diverged). A simulation
/// takes its rest lengths from the groom it is made from, so nudging its hair moves its rest
/// pose as well: a change of the model by 1e-7 m, where the references' springs start 1e-7 m
/// from rest. Either is a perturbation far below the spreads judged (1e-5 m).
pub fn run_simulations(sc: &ReportScene, params: &SimParams, members: usize) -> Vec<Option<Statistics>> {
    each_member(members, |k| {
        let g = &sc.groom;
        let pos: Vec<Vec3> = g
            .positions()
            .iter()
            .zip(g.pinned())
            .enumerate()
            .map(|(i, (&p, &pinned))| {
                if pinned {
                    p
                } else {
                    (p.as_dvec3() + nudge(k, i)).as_vec3()
                }
            })
            .collect();
        let counts: Vec<u32> = (0..g.strand_count()).map(|s| g.strand_range(s).len() as u32).collect();
        let groom = Groom::new(pos, &counts, Some(g.pinned().to_vec()), Some(g.masses().to_vec()), 1.0)
            .expect("the scene's groom, nudged");
        let hair = g.point_count();
        let water: Vec<Vec3> = sc
            .water
            .iter()
            .enumerate()
            .map(|(j, &p)| (p.as_dvec3() + nudge(k, hair + j)).as_vec3())
            .collect();
        let scene = ReportScene {
            groom,
            water,
            params: params.clone(),
            name: sc.name,
            soak: sc.soak,
        };
        let mut sim = scene.simulation(params.clone()).expect("valid scene");
        (0..60).all(|_| sim.step(1.0 / 60.0).is_ok()).then(|| {
            let x: Vec<DVec3> = sim.positions().iter().map(|p| p.as_dvec3()).collect();
            Statistics::of(sc, &x, sim.energy().total())
        })
    })
}

/// `member(k)` for k in 0..members, on every core, returned in member order (member k's
/// result is the same whichever thread computes it; these runs are untimed).
fn each_member<T: Send>(members: usize, member: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(members.max(1));
    let per_thread = members.div_ceil(threads).max(1);
    let mut out: Vec<Option<T>> = (0..members).map(|_| None).collect();
    std::thread::scope(|s| {
        for (w, slots) in out.chunks_mut(per_thread).enumerate() {
            let first = w * per_thread;
            let member = &member;
            s.spawn(move || {
                for (j, slot) in slots.iter_mut().enumerate() {
                    *slot = Some(member(first + j));
                }
            });
        }
    });
    out.into_iter().map(|m| m.expect("every member ran")).collect()
}
