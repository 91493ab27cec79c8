//! Honest error on chaotic scenes. Where water clumps the hair, moving one droplet by 1e-7 m
//! moves the hair by far more within a second (a strand caught by a droplet in one run and not
//! in another), so a pointwise error below that spread cannot rank integrators. Instead, an
//! ensemble of reference runs whose hair and water are nudged by [`NUDGE`] sets a band for each
//! statistic the eye sees (how clumped, how much energy, where each strand hangs), and an
//! integrator's run whose statistics lie in the band counts as converged.

use glam::{DVec3, Vec3};
use wethair::physics::clumping::mean_nearest_along_strands;
use wethair::scenes::ReportScene;

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
        let centre_spread = members
            .iter()
            .map(|m| rms_distance(&m.centres, &mean_centres))
            .fold(0.0, f64::max);
        Band {
            clumping: range(&|m| m.clumping),
            energy: range(&|m| m.energy),
            mean_centres,
            centre_spread,
        }
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

/// The statistics at `t` of `members` references of `sc` (RK4 at step `h`), member `k`'s
/// every free hair point and every water particle moved by [`NUDGE`], each in its own
/// direction. The hair is nudged as well as the water: a judged run's own error (and its f32
/// rounding) reaches the hair points directly, not through the droplets, and the droplets
/// alone span a band 0.6x as wide on the wet patch.
pub fn run(sc: &ReportScene, members: usize, t: f64, h: f64) -> Vec<Statistics> {
    let member = |k: u64| {
        let mut r = sc.reference().moved(|i| NUDGE * direction(mix(k + 1) ^ i as u64));
        r.run_to(t, h);
        Statistics::of(sc, r.hair_positions(), r.energy())
    };
    // The members are independent and untimed: they run on every core, member k's result the
    // same whichever thread computes it, and are returned in member order.
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(members.max(1));
    let per_thread = members.div_ceil(threads).max(1);
    let mut out: Vec<Option<Statistics>> = vec![None; members];
    std::thread::scope(|s| {
        for (w, slots) in out.chunks_mut(per_thread).enumerate() {
            let first = w * per_thread;
            let member = &member;
            s.spawn(move || {
                for (j, slot) in slots.iter_mut().enumerate() {
                    *slot = Some(member((first + j) as u64));
                }
            });
        }
    });
    out.into_iter().map(|m| m.expect("every member ran")).collect()
}
