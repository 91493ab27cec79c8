//! The f64 reference: the same model (eq. 1 springs with either damping, gravity, drag, eq. 2
//! adhesion between hair and water, both integrated as mass points) written plainly in f64 and
//! integrated with classical fourth-order Runge-Kutta at a small fixed step. It is what the
//! work-precision report measures every integrator against.
//!
//! Scope: the head stays where it is (pinned points are fixed), no colliders, adhesion by brute
//! force over all pairs (the report's scenes hold few particles). `tests/reference.rs` checks
//! that halving its step changes the 1 s result by less than 1e-9 m on the report's scenes.

use crate::groom::Groom;
use crate::params::SimParams;
use crate::physics::spring::DampingModel;
use glam::DVec3;

/// One spring of the reference: endpoints, rest length (m), stiffness (N/m), damping (N·s/m).
#[derive(Clone, Copy, Debug)]
struct Spring {
    a: usize,
    b: usize,
    rest: f64,
    k: f64,
    c: f64,
}

/// Positions and velocities of hair points then water particles.
#[derive(Clone, Debug)]
struct State {
    x: Vec<DVec3>,
    v: Vec<DVec3>,
}

/// The f64 model of one scene.
#[derive(Clone, Debug)]
pub struct Reference {
    state: State,
    inv_mass: Vec<f64>,
    mass: Vec<f64>,
    hair: usize,
    springs: Vec<Spring>,
    axial: bool,
    gravity: DVec3,
    /// Each hair point's air drag, N·s/m (`physics/per_length.rs`'s law, in f64).
    drag: Vec<f64>,
    water_drag: f64,
    r_min: f64,
    r_max: f64,
    adhesion: f64,
    /// Each hair point's share of eq. 2's pull (1, or its hair over `water.adhesion_length`).
    adhesion_share: Vec<f64>,
    /// Simulated time, s.
    pub time: f64,
}

impl Reference {
    /// The reference for `groom` with `params`' springs, damping, gravity, drag and water
    /// parameters, and `water` particles at rest.
    pub fn new(groom: &Groom, params: &SimParams, water: &[glam::Vec3]) -> Self {
        let hair = groom.point_count();
        let mut x: Vec<DVec3> = groom.positions().iter().map(|p| p.as_dvec3()).collect();
        x.extend(water.iter().map(|p| p.as_dvec3()));
        let n = x.len();
        let m_w = params.water.particle_mass as f64;
        let mut inv_mass = Vec::with_capacity(n);
        let mut mass = Vec::with_capacity(n);
        for (i, &m) in groom.masses().iter().enumerate() {
            let pinned = groom.pinned()[i];
            inv_mass.push(if pinned { 0.0 } else { 1.0 / m as f64 });
            mass.push(if pinned { 0.0 } else { m as f64 });
        }
        inv_mass.extend(std::iter::repeat_n(1.0 / m_w, water.len()));
        mass.extend(std::iter::repeat_n(m_w, water.len()));
        let mut springs = Vec::new();
        // Rest lengths and constants from the f32 rest pose, as both backends take them.
        let sp = crate::plan::point_springs(groom, params);
        let bend = crate::plan::has_bend(params, groom.max_strand_points());
        // `physics/per_length.rs`'s law: the hair a point stands for, half of each rest
        // segment it ends, over the length a coefficient is quoted over.
        let mut drag = vec![params.air_drag as f64; hair];
        let mut adhesion_share = vec![1.0; hair];
        let (drag_length, adhesion_length) = (params.air_drag_length as f64, params.water.adhesion_length as f64);
        for s in 0..groom.strand_count() {
            let r = groom.strand_range(s);
            for i in r.clone() {
                let before = if i > r.start { sp[i - 1].rest[0] as f64 } else { 0.0 };
                let length = 0.5 * (before + sp[i].rest[0] as f64);
                if drag_length > 0.0 {
                    drag[i] = params.air_drag as f64 * length / drag_length;
                }
                if adhesion_length > 0.0 {
                    adhesion_share[i] = length / adhesion_length;
                }
                if i + 1 < r.end {
                    springs.push(Spring {
                        a: i,
                        b: i + 1,
                        rest: sp[i].rest[0] as f64,
                        k: sp[i].stretch.stiffness as f64,
                        c: sp[i].stretch.damping as f64,
                    });
                }
                if i + 2 < r.end && bend {
                    springs.push(Spring {
                        a: i,
                        b: i + 2,
                        rest: sp[i].rest[1] as f64,
                        k: sp[i].bend.stiffness as f64,
                        c: sp[i].bend.damping as f64,
                    });
                }
            }
        }
        let w = &params.water;
        Reference {
            state: State {
                v: vec![DVec3::ZERO; n],
                x,
            },
            inv_mass,
            mass,
            hair,
            springs,
            axial: params.damping_model == DampingModel::AXIAL,
            gravity: params.gravity.as_dvec3(),
            drag,
            water_drag: w.drag as f64,
            r_min: w.r_min as f64,
            r_max: w.r_max as f64,
            adhesion: w.adhesion as f64,
            adhesion_share,
            time: 0.0,
        }
    }

    /// The same scene with every hair point soaked to `soak` of its hold limit, held still
    /// (the wet model with no flow, drip, drying or absorption): a free point weighs its dry
    /// mass times `1 + soak × (capacity_ratio + free_ratio)`, and every bend spring's stiffness
    /// (not its damping) is scaled by `1 - (1 - wet_bend_ratio) × s`, `s` the water over the
    /// capacity (docs/WET_MODEL.md §3-§4, written here again in f64).
    pub fn soaked(mut self, soak: f64, held: &crate::params::HeldWater) -> Self {
        let (cap, free) = (held.capacity_ratio as f64, held.free_ratio as f64);
        let gain = 1.0 + soak * (cap + free);
        let saturation = if cap > 0.0 { soak * (cap + free) / cap } else { 0.0 };
        for i in 0..self.hair {
            if self.inv_mass[i] > 0.0 {
                self.mass[i] *= gain;
                self.inv_mass[i] = 1.0 / self.mass[i];
            }
        }
        let limp = 1.0 - (1.0 - held.wet_bend_ratio as f64) * saturation.clamp(0.0, 1.0);
        for sp in &mut self.springs {
            if sp.b == sp.a + 2 {
                sp.k *= limp;
            }
        }
        self
    }

    /// The same scene with every free point (hair points not pinned, and water particles)
    /// moved by `offset(i)`, `i` counting hair points in the groom's order and then the
    /// particles: a member of an ensemble perturbed at its start. Rest lengths stay those of
    /// the groom, so only the state is perturbed, not the model.
    pub fn moved(mut self, offset: impl Fn(usize) -> DVec3) -> Self {
        for (i, x) in self.state.x.iter_mut().enumerate() {
            if self.inv_mass[i] > 0.0 {
                *x += offset(i);
            }
        }
        self
    }

    /// Accelerations of every point at `s`.
    fn accel(&self, s: &State, out: &mut [DVec3]) {
        let f = out;
        for (i, fi) in f.iter_mut().enumerate() {
            let drag = if i < self.hair { self.drag[i] } else { self.water_drag };
            *fi = -drag * s.v[i];
        }
        for sp in &self.springs {
            let d = s.x[sp.b] - s.x[sp.a];
            let len = d.length();
            let n = if len > 1e-12 { d / len } else { DVec3::ZERO };
            let dv = s.v[sp.b] - s.v[sp.a];
            let fa = if self.axial {
                (sp.k * (len - sp.rest) + sp.c * dv.dot(n)) * n
            } else {
                sp.k * (len - sp.rest) * n + sp.c * dv
            };
            f[sp.a] += fa;
            f[sp.b] -= fa;
        }
        // Eq. 2 over all hair-water pairs.
        let r2 = self.r_max * self.r_max;
        for j in self.hair..s.x.len() {
            for i in 0..self.hair {
                let d = s.x[j] - s.x[i];
                let d2 = d.length_squared();
                if d2 > r2 || d2 < 1e-18 {
                    continue;
                }
                let dist = d2.sqrt();
                let u = (2.0 * dist - self.r_min - self.r_max) / (self.r_min - self.r_max);
                let fh = d * (self.adhesion * (1.0 - u * u) / dist * self.adhesion_share[i]);
                f[i] += fh;
                f[j] -= fh;
            }
        }
        for (i, fi) in f.iter_mut().enumerate() {
            *fi = if self.inv_mass[i] > 0.0 {
                *fi * self.inv_mass[i] + self.gravity
            } else {
                DVec3::ZERO
            };
        }
    }

    /// Which hair-water pairs are within `r_max` (a hash of the set): eq. 2's force has a kink
    /// there, and a Runge-Kutta step across it loses its order.
    fn pair_signature(&self, s: &State) -> (usize, u64) {
        let r2 = self.r_max * self.r_max;
        let (mut n, mut h) = (0usize, 0u64);
        for j in self.hair..s.x.len() {
            for i in 0..self.hair {
                if (s.x[j] - s.x[i]).length_squared() <= r2 {
                    n += 1;
                    h = h.wrapping_add(
                        (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ (j as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f),
                    );
                }
            }
        }
        (n, h)
    }

    /// One RK4 step of `h`, split in halves (down to `h / 2^depth`) while a pair crosses
    /// `r_max` inside it, so that steps across eq. 2's kink are tiny and the reference keeps
    /// converging at high order on wet scenes.
    pub fn step(&mut self, h: f64) {
        self.step_split(h, 16);
    }

    fn step_split(&mut self, h: f64, depth: u32) {
        if self.state.x.len() == self.hair || depth == 0 {
            self.step_rk4(h);
            return;
        }
        let before = self.pair_signature(&self.state);
        let saved = (self.state.clone(), self.time);
        self.step_rk4(h);
        if self.pair_signature(&self.state) != before {
            (self.state, self.time) = saved;
            self.step_split(h / 2.0, depth - 1);
            self.step_split(h / 2.0, depth - 1);
        }
    }

    /// One classical RK4 step of `h` seconds.
    fn step_rk4(&mut self, h: f64) {
        let n = self.state.x.len();
        let s0 = self.state.clone();
        let mut k = [
            vec![DVec3::ZERO; n],
            vec![DVec3::ZERO; n],
            vec![DVec3::ZERO; n],
            vec![DVec3::ZERO; n],
        ];
        let mut kv = [
            vec![DVec3::ZERO; n],
            vec![DVec3::ZERO; n],
            vec![DVec3::ZERO; n],
            vec![DVec3::ZERO; n],
        ];
        let mut tmp = s0.clone();
        for stage in 0..4 {
            let c = [0.0, 0.5, 0.5, 1.0][stage];
            if stage > 0 {
                for i in 0..n {
                    tmp.x[i] = s0.x[i] + c * h * kv[stage - 1][i];
                    tmp.v[i] = s0.v[i] + c * h * k[stage - 1][i];
                }
            }
            self.accel(&tmp, &mut k[stage]);
            kv[stage].copy_from_slice(&tmp.v);
        }
        for i in 0..n {
            self.state.x[i] += h / 6.0 * (kv[0][i] + 2.0 * kv[1][i] + 2.0 * kv[2][i] + kv[3][i]);
            self.state.v[i] += h / 6.0 * (k[0][i] + 2.0 * k[1][i] + 2.0 * k[2][i] + k[3][i]);
        }
        self.time += h;
    }

    /// Advances to time `t` in steps of at most `h`.
    pub fn run_to(&mut self, t: f64, h: f64) {
        let steps = ((t - self.time) / h).ceil().max(0.0) as usize;
        let hh = (t - self.time) / steps.max(1) as f64;
        for _ in 0..steps {
            self.step(hh);
        }
    }

    /// Hair point positions (host order).
    pub fn hair_positions(&self) -> &[DVec3] {
        &self.state.x[..self.hair]
    }

    /// Kinetic + spring + gravitational energy of hair and water, J.
    pub fn energy(&self) -> f64 {
        let s = &self.state;
        let mut e = 0.0;
        for i in 0..s.x.len() {
            e += 0.5 * self.mass[i] * s.v[i].length_squared() - self.mass[i] * self.gravity.dot(s.x[i]);
        }
        for sp in &self.springs {
            let len = (s.x[sp.b] - s.x[sp.a]).length();
            e += 0.5 * sp.k * (len - sp.rest).powi(2);
        }
        e
    }
}
