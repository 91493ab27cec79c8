//! Implicit (backward) Euler for `W` strands at once, with a direct banded solve per strand.
//!
//! Backward Euler's positions minimise the incremental potential (Gast et al. 2015)
//!
//! `E(x) = Σ m/(2h²) |x - x̃|² + Σ_springs ½ k (|x_b - x_a| - l)² + Σ_springs (c/2h) |P Δd|²`,
//!
//! with `x̃ = x + h v + h² (f_ext/m + g)` (adhesion and cohesion stay explicit), `Δd` the change of a
//! spring's vector over the step and `P` its damping projector (`n nᵀ` axial, `I` the paper's).
//! Air drag `c (w - v)` toward the wind `w` is implicit: its potential `c/(2h) |x - x₀ - h w|²`
//! is a diagonal quadratic, so it folds into the inertial term as a heavier mass `m + h c` and a
//! target moved toward `x₀ + h w` (stable at any drag, and second order under BDF2).
//! Each iteration takes a Newton step `H d = -∇E`; `H = M/h² + K + C/h` has a spring's 3×3
//! blocks two points apart, so it is banded (half-bandwidth 8) and, with the lateral term
//! `1 - l/|d|` clamped at 0, symmetric positive definite: a banded Cholesky solves it in
//! O(points) per strand, one strand per lane (and per GPU invocation). A backtracking line search
//! per strand keeps every step downhill, so stiff springs cannot blow up. Iterations start from
//! the inertial guess `x + h v`; one iteration is a linearised step made safe, two keep the
//! energy within 1% of M g L at 10^6 times the explicit limit, more converge to exact backward
//! Euler. Pinned points sit on the head's target. Then `v = (x_1 - x)/h`.
//!
//! Energies, the matrix and the solve are f64: at stiffness 10^6 times the explicit limit the
//! system's condition number is ~10^6 and f32 would lose ~10% of the step. State stays f32.

use super::bdf2::{keep_rows, keep_velocity_rounding, start_rows, Bdf2Row};
use super::lanes::{ParamRow, StateRow, L3, W};
use super::per_length::PerLength;
use super::spring::{SpringLanes, MIN_LENGTH};

/// Half-bandwidth of a strand's matrix in scalars (a bend spring couples DOFs 6 ± 2 apart).
pub const BAND: usize = 8;

/// Smallest pivot the GPU's f32 Cholesky takes (`implicit.wgsl`); this file's f64 solve
/// floors at 1e-300. Both only keep a singular system from dividing by zero.
pub const PIVOT_FLOOR_F32: f32 = 1e-30;

/// Sufficient decrease the Armijo line search asks of a step (both solves).
pub const ARMIJO_C1: f64 = 1e-4;

/// Relative slack in the GPU's f32 Armijo test (`implicit.wgsl`), where the f64 line search
/// here allows 1e-12: f32 energies of a whole strand round at about 1e-7 of their size.
pub const ARMIJO_SLACK_F32: f32 = 1e-6;

/// One f64 per strand of a lane group.
pub type LaneD = [f64; W];

/// Per-worker storage for one block's banded system (allocated once, at create).
#[derive(Debug, Default)]
pub struct BandScratch {
    /// Lower band: `a[r][k]` is the entry (r, r - k).
    a: Vec<[LaneD; BAND + 1]>,
    rhs: Vec<LaneD>,
    /// The start (BDF2's blended start x̂, never rounded), the inertial target x̃ and the
    /// current iterate (f64, per DOF).
    start: Vec<LaneD>,
    /// The start's velocities v̂ (f64, per DOF).
    vstart: Vec<LaneD>,
    target: Vec<LaneD>,
    x: Vec<LaneD>,
    trial: Vec<LaneD>,
    grad: Vec<LaneD>,
    /// Each point's inertial mass under implicit drag, `m + h c` (0 pinned; [`inertia`]).
    mass: Vec<LaneD>,
    /// Each spring at the substep's start (stretch springs, then bend), for its damping.
    starts: Vec<SpringStart>,
}

/// `f` of each lane: a line of lane arithmetic written once, which the compiler runs as one
/// vector operation. Generic over `f`: taking `&dyn Fn` (once measured 10% faster) relied on
/// the compiler seeing through each call, and a change elsewhere in the block kernel made it
/// stop: every lane became an indirect call, out of the kernel's AVX2 build (BDF2 on the wet
/// paper scene 16 -> 25 ms of blocks a frame). Generic, the dry implicit step measured the same.
#[inline(always)]
fn lanes(f: &impl Fn(usize) -> f64) -> LaneD {
    std::array::from_fn(f)
}

/// A spring's vector at the substep's start and its direction (zero when shorter than
/// [`MIN_LENGTH`]): the same for every Newton iteration and line-search trial, so computed once.
#[derive(Clone, Copy, Debug, Default)]
struct SpringStart {
    d0: [LaneD; 3],
    n0: [LaneD; 3],
}

/// The start as the state holds it, widened to f64 per DOF (`3 i + c`): backward Euler's, and
/// BDF2's at a restart.
#[inline(always)]
pub fn start_of_state(state: &[StateRow], x: &mut [LaneD], v: &mut [LaneD]) {
    for (i, st) in state.iter().enumerate() {
        for (c, (p, q)) in [(&st.x.x, &st.v.x), (&st.x.y, &st.v.y), (&st.x.z, &st.v.z)]
            .into_iter()
            .enumerate()
        {
            for l in 0..W {
                x[3 * i + c][l] = p[l] as f64;
                v[3 * i + c][l] = q[l] as f64;
            }
        }
    }
}

/// Point `i`'s three DOFs of a per-DOF array.
#[inline(always)]
fn dof3(x: &[LaneD], i: usize) -> &[LaneD; 3] {
    x[3 * i..3 * i + 3].try_into().expect("three DOFs")
}

impl SpringStart {
    /// The spring from row `a` to row `b` of the state (backward Euler's start).
    #[inline(always)]
    fn of_state(x0: &[StateRow], a: usize, b: usize) -> SpringStart {
        let (pa, pb) = (&x0[a].x, &x0[b].x);
        SpringStart::of_vector([
            lanes(&|l| (pb.x[l] - pa.x[l]) as f64),
            lanes(&|l| (pb.y[l] - pa.y[l]) as f64),
            lanes(&|l| (pb.z[l] - pa.z[l]) as f64),
        ])
    }

    /// The spring from point `a` to point `b` of a start given per DOF (BDF2's, in f64).
    #[inline(always)]
    fn of_start(x0: &[LaneD], a: usize, b: usize) -> SpringStart {
        let (pa, pb) = (dof3(x0, a), dof3(x0, b));
        SpringStart::of_vector([
            lanes(&|l| pb[0][l] - pa[0][l]),
            lanes(&|l| pb[1][l] - pa[1][l]),
            lanes(&|l| pb[2][l] - pa[2][l]),
        ])
    }

    #[inline(always)]
    fn of_vector(d0: [LaneD; 3]) -> SpringStart {
        let len0 = lanes(&|l| (d0[0][l] * d0[0][l] + d0[1][l] * d0[1][l] + d0[2][l] * d0[2][l]).sqrt());
        let min_len = MIN_LENGTH as f64;
        let unit = |r: usize| lanes(&|l| if len0[l] > min_len { d0[r][l] / len0[l] } else { 0.0 });
        let n0 = [unit(0), unit(1), unit(2)];
        SpringStart { d0, n0 }
    }
}

impl BandScratch {
    /// Storage for strands of up to `points` points.
    pub fn new(points: usize) -> Self {
        BandScratch {
            a: vec![[[0.0; W]; BAND + 1]; 3 * points],
            rhs: vec![[0.0; W]; 3 * points],
            start: vec![[0.0; W]; 3 * points],
            vstart: vec![[0.0; W]; 3 * points],
            target: vec![[0.0; W]; 3 * points],
            x: vec![[0.0; W]; 3 * points],
            trial: vec![[0.0; W]; 3 * points],
            grad: vec![[0.0; W]; 3 * points],
            mass: vec![[0.0; W]; points],
            starts: vec![SpringStart::default(); 2 * points],
        }
    }
}

/// One spring's share of the energy (times h²) and, when asked, of its gradient (times h², into
/// `grad`) and of the Hessian (times h², into the band).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn spring_terms<const AXIAL: bool>(
    x: &[LaneD],
    start: &SpringStart,
    a: usize,
    b: usize,
    s: &SpringLanes,
    h: f64,
    energy: &mut LaneD,
    grad: Option<&mut [LaneD]>,
    band: Option<&mut [[LaneD; BAND + 1]]>,
) {
    let off = 3 * (b - a);
    // Lanes innermost in every loop, so each line is one vector operation over the strands
    // (written lane by lane, with per-lane branches, the compiler kept it scalar: half of an
    // implicit step). Each lane's operations are those of a one-strand spring, in its order.
    let (hh, min_len) = (h * h, MIN_LENGTH as f64);
    let d: [LaneD; 3] = std::array::from_fn(|r| lanes(&|l| x[3 * b + r][l] - x[3 * a + r][l]));
    let len = lanes(&|l| (d[0][l] * d[0][l] + d[1][l] * d[1][l] + d[2][l] * d[2][l]).sqrt());
    let inv = lanes(&|l| if len[l] > min_len { 1.0 / len[l] } else { 0.0 });
    let n: [LaneD; 3] = std::array::from_fn(|r| lanes(&|l| d[r][l] * inv[l]));
    let k = lanes(&|l| s.k[l] as f64);
    let rest = lanes(&|l| s.rest[l] as f64);
    // (c/h) h²
    let ch = lanes(&|l| h * s.c[l] as f64);
    // Damping potential about the spring's vector at the start of the step.
    let (d0, n0) = (&start.d0, &start.n0);
    let dd: [LaneD; 3] = std::array::from_fn(|r| lanes(&|l| d[r][l] - d0[r][l]));
    let stretch = lanes(&|l| if len[l] > min_len { len[l] - rest[l] } else { 0.0 });
    let (pdd, damp_e) = if AXIAL {
        let t = lanes(&|l| n0[0][l] * dd[0][l] + n0[1][l] * dd[1][l] + n0[2][l] * dd[2][l]);
        (
            std::array::from_fn(|r| lanes(&|l| n0[r][l] * t[l])),
            lanes(&|l| t[l] * t[l]),
        )
    } else {
        (
            dd,
            lanes(&|l| dd[0][l] * dd[0][l] + dd[1][l] * dd[1][l] + dd[2][l] * dd[2][l]),
        )
    };
    for l in 0..W {
        energy[l] += hh * 0.5 * k[l] * stretch[l] * stretch[l] + 0.5 * ch[l] * damp_e[l];
    }
    let Some(grad) = grad else {
        return; // the line search's trial: its energy only
    };
    for r in 0..3 {
        for l in 0..W {
            let gr = hh * k[l] * stretch[l] * n[r][l] + ch[l] * pdd[r][l];
            grad[3 * b + r][l] += gr;
            grad[3 * a + r][l] -= gr;
        }
    }
    let Some(band) = band else {
        return;
    };
    let alpha = lanes(&|l| {
        if len[l] > min_len {
            (1.0 - rest[l] * inv[l]).max(0.0)
        } else {
            0.0
        }
    });
    for r in 0..3 {
        for q in 0..3 {
            let id = if r == q { 1.0 } else { 0.0 };
            let v = lanes(&|l| {
                let damp = if AXIAL { n0[r][l] * n0[q][l] } else { id };
                hh * k[l] * (alpha[l] * id + (1.0 - alpha[l]) * n[r][l] * n[q][l]) + ch[l] * damp
            });
            for l in 0..W {
                if q <= r {
                    band[3 * a + r][r - q][l] += v[l];
                    band[3 * b + r][r - q][l] += v[l];
                }
                band[3 * b + r][off + r - q][l] -= v[l];
            }
        }
    }
}

/// Energy (times h²) of the whole strand at `x`; its gradient and Hessian too when asked.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn strand_terms<const AXIAL: bool>(
    x: &[LaneD],
    starts: &[SpringStart],
    target: &[LaneD],
    rows: &[ParamRow],
    mass: &[LaneD],
    bend: bool,
    h: f64,
    mut grad: Option<&mut [LaneD]>,
    mut band: Option<&mut [[LaneD; BAND + 1]]>,
) -> LaneD {
    let p = x.len() / 3;
    let mut energy = [0.0f64; W];
    for i in 0..p {
        let m = mass[i];
        for c in 0..3 {
            for l in 0..W {
                let e = x[3 * i + c][l] - target[3 * i + c][l];
                energy[l] += 0.5 * m[l] * e * e;
                if let Some(g) = grad.as_deref_mut() {
                    g[3 * i + c][l] = m[l] * e;
                }
            }
        }
        if let Some(band) = band.as_deref_mut() {
            for c in 0..3 {
                band[3 * i + c] = [[0.0; W]; BAND + 1];
                for l in 0..W {
                    band[3 * i + c][0][l] = if m[l] > 0.0 { m[l] } else { 1.0 };
                }
            }
        }
    }
    // Stretch springs join i to i+1, bend springs i to i+2.
    for (gap, on) in [(1, true), (2, bend)] {
        for i in (0..p.saturating_sub(gap)).filter(|_| on) {
            let s = if gap == 1 { &rows[i].stretch } else { &rows[i].bend };
            let (g, start) = (grad.as_deref_mut(), &starts[(gap - 1) * p + i]);
            spring_terms::<AXIAL>(x, start, i, i + gap, s, h, &mut energy, g, band.as_deref_mut());
        }
    }
    energy
}

/// The inertial term's mass of a point with inverse mass `w` under drag `hc = h c`: `m + h c`
/// (0 for a pinned point; `c` the point's own, [`PerLength::row`]).
#[inline(always)]
fn inertia(w: f32, hc: f64) -> f64 {
    if w > 0.0 {
        1.0 / w as f64 + hc
    } else {
        0.0
    }
}

/// Advances one block of `W` strands by `h` with implicit Euler: `iterations` Newton steps on
/// the incremental potential, each with a per-strand backtracking line search. `f_ext` holds
/// the explicit forces (adhesion, cohesion); `drag` pulls toward `wind` implicitly;
/// `target(i)` the head's target for rows with pinned lanes. `bdf2`: BDF2's history and this
/// substep's `b` (the solve starts from the blended start and keeps the history,
/// [`super::bdf2::start_rows`], [`super::bdf2::keep_rows`]); `None` for backward Euler.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn implicit_euler_block<const AXIAL: bool>(
    state: &mut [StateRow],
    f_ext: &[L3],
    rows: &[ParamRow],
    target: &dyn Fn(usize) -> Option<L3>,
    bend: bool,
    g: [f32; 3],
    (drag, wind): (PerLength, [f32; 3]),
    h: f32,
    iterations: u32,
    mut bdf2: Option<(&mut [Bdf2Row], f32)>,
    sc: &mut BandScratch,
) {
    let p = state.len();
    debug_assert!(bdf2.as_ref().is_none_or(|(hist, _)| hist.len() == p));
    let n = 3 * p;
    let hd = h as f64;
    for i in 0..p {
        let c = drag.row(rows, i);
        sc.mass[i] = std::array::from_fn(|l| inertia(rows[i].inv_mass[l], hd * c[l] as f64));
    }
    // The start (x̂, v̂): the state as it is, or BDF2's blend of it and its history.
    match &bdf2 {
        Some((hist, b)) => start_rows(state, hist, *b, &mut sc.start[..n], &mut sc.vstart[..n]),
        None => start_of_state(state, &mut sc.start[..n], &mut sc.vstart[..n]),
    }
    // Inertial target x̃, and the start iterate x = x + h v (free points; far more accurate
    // than starting where they were, which makes one iteration damp rotation), pinned points on
    // the head's target, where they stay.
    for i in 0..p {
        let t = target(i);
        let f = &f_ext[i];
        let (xs, vs) = (dof3(&sc.start, i), dof3(&sc.vstart, i));
        for l in 0..W {
            let w = rows[i].inv_mass[l];
            let fs = [f.x[l], f.y[l], f.z[l]];
            let pin = t.as_ref().filter(|_| w == 0.0).map(|t| [t.x[l], t.y[l], t.z[l]]);
            // With drag: the target weighted toward x0 + h wind by h c against m.
            let m = if w > 0.0 { 1.0 / w as f64 } else { 0.0 };
            let mw = m / sc.mass[i][l].max(f64::MIN_POSITIVE);
            for c in 0..3 {
                let (x0, v0) = (xs[c][l], vs[c][l]);
                let inertial = x0 + hd * v0 + hd * hd * (fs[c] * w + g[c]) as f64;
                let dragged = x0 + hd * wind[c] as f64;
                sc.target[3 * i + c][l] = mw * inertial + (1.0 - mw) * dragged;
                sc.x[3 * i + c][l] = pin.map_or(x0 + hd * v0, |t| t[c] as f64);
            }
        }
    }
    for (gap, on) in [(1, true), (2, bend)] {
        for i in (0..p.saturating_sub(gap)).filter(|_| on) {
            sc.starts[(gap - 1) * p + i] = if bdf2.is_some() {
                SpringStart::of_start(&sc.start[..n], i, i + gap)
            } else {
                SpringStart::of_state(state, i, i + gap)
            };
        }
    }
    for _ in 0..iterations.max(1) {
        let e0 = strand_terms::<AXIAL>(
            &sc.x[..n],
            &sc.starts[..2 * p],
            &sc.target[..n],
            rows,
            &sc.mass[..p],
            bend,
            hd,
            Some(&mut sc.grad[..n]),
            Some(&mut sc.a[..n]),
        );
        // Newton direction d = -H⁻¹ ∇E; pinned DOFs do not move (identity rows, zero gradient).
        for i in 0..p {
            for l in 0..W {
                if rows[i].inv_mass[l] > 0.0 {
                    continue;
                }
                for c in 0..3 {
                    let pcol = 3 * i + c;
                    for k in 1..=BAND {
                        if pcol + k < n {
                            sc.a[pcol + k][k][l] = 0.0;
                        }
                        if k <= pcol {
                            sc.a[pcol][k][l] = 0.0;
                        }
                    }
                    sc.a[pcol][0][l] = 1.0;
                    sc.grad[pcol][l] = 0.0;
                }
            }
        }
        for r in 0..n {
            sc.rhs[r] = sc.grad[r].map(|v| -v);
        }
        solve_banded(&mut sc.a[..n], &mut sc.rhs[..n]);
        // Directional derivative ∇E·d (negative: H is positive definite).
        let mut slope = [0.0f64; W];
        for r in 0..n {
            for l in 0..W {
                slope[l] += sc.grad[r][l] * sc.rhs[r][l];
            }
        }
        // Backtracking line search, per strand (Armijo, at most 12 halvings).
        let mut step = [1.0f64; W];
        let mut done = [false; W];
        for _ in 0..12 {
            for r in 0..n {
                for l in 0..W {
                    sc.trial[r][l] = sc.x[r][l] + step[l] * sc.rhs[r][l];
                }
            }
            let e = strand_terms::<AXIAL>(
                &sc.trial[..n],
                &sc.starts[..2 * p],
                &sc.target[..n],
                rows,
                &sc.mass[..p],
                bend,
                hd,
                None,
                None,
            );
            let mut all = true;
            for l in 0..W {
                if !done[l] {
                    // A NaN energy fails the test, so a step that overflows is halved away.
                    if e[l] <= e0[l] + ARMIJO_C1 * step[l] * slope[l] + 1e-12 * e0[l].abs() {
                        done[l] = true;
                    } else {
                        step[l] *= 0.5;
                        all = false;
                    }
                }
            }
            if all {
                break;
            }
        }
        for r in 0..n {
            for l in 0..W {
                let s = if done[l] { step[l] } else { 0.0 };
                sc.x[r][l] += s * sc.rhs[r][l];
            }
        }
    }
    if let Some((hist, b)) = &mut bdf2 {
        keep_rows(hist, state, *b, &sc.x[..n]);
    }
    let inv_h = 1.0 / hd;
    for (i, st) in state.iter_mut().enumerate() {
        let (x1, start) = (dof3(&sc.x, i), dof3(&sc.start, i));
        for l in 0..W {
            let x1 = [x1[0][l], x1[1][l], x1[2][l]];
            let start = [start[0][l], start[1][l], start[2][l]];
            st.v.x[l] = ((x1[0] - start[0]) * inv_h) as f32;
            st.v.y[l] = ((x1[1] - start[1]) * inv_h) as f32;
            st.v.z[l] = ((x1[2] - start[2]) * inv_h) as f32;
            st.x.x[l] = x1[0] as f32;
            st.x.y[l] = x1[1] as f32;
            st.x.z[l] = x1[2] as f32;
        }
    }
    if let Some((hist, _)) = &mut bdf2 {
        keep_velocity_rounding(hist, state, &sc.x[..n], &sc.start[..n], inv_h);
    }
}

/// Solves `A y = b` in place (`b` becomes `y`) for a symmetric positive definite banded `A`
/// given by its lower band, by Cholesky `L Lᵀ` (overwriting `A` with `L`). Every loop runs
/// the lanes innermost, so each multiply-subtract is one vector operation over the strands;
/// with a strand's sum outermost the compiler kept them scalar (two-thirds of an implicit
/// step). Each lane's operations, and so its bits, are those of a one-strand solve.
#[inline(always)]
pub fn solve_banded(a: &mut [[LaneD; BAND + 1]], b: &mut [LaneD]) {
    let n = a.len();
    for r in 0..n {
        for k in (1..=BAND.min(r)).rev() {
            let c = r - k;
            // L[r][c] = (A[r][c] - Σ_{j < c} L[r][j] L[c][j]) / L[c][c]
            let mut s = a[r][k];
            for j in (k + 1)..=BAND.min(r) {
                let (lr, lc) = (a[r][j], a[c][j - k]);
                for l in 0..W {
                    s[l] -= lr[l] * lc[l];
                }
            }
            let d = a[c][0];
            for l in 0..W {
                a[r][k][l] = s[l] / d[l];
            }
        }
        let mut s = a[r][0];
        for k in 1..=BAND.min(r) {
            let lr = a[r][k];
            for l in 0..W {
                s[l] -= lr[l] * lr[l];
            }
        }
        for l in 0..W {
            a[r][0][l] = s[l].max(1e-300).sqrt();
        }
    }
    for r in 0..n {
        let mut s = b[r];
        for k in 1..=BAND.min(r) {
            let (lr, y) = (a[r][k], b[r - k]);
            for l in 0..W {
                s[l] -= lr[l] * y[l];
            }
        }
        for l in 0..W {
            b[r][l] = s[l] / a[r][0][l];
        }
    }
    for r in (0..n).rev() {
        let mut s = b[r];
        for k in 1..=BAND.min(n - 1 - r) {
            let (lk, y) = (a[r + k][k], b[r + k]);
            for l in 0..W {
                s[l] -= lk[l] * y[l];
            }
        }
        for l in 0..W {
            b[r][l] = s[l] / a[r][0][l];
        }
    }
}
