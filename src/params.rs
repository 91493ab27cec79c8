//! The simulation description: every physical parameter with its unit, its default (the paper
//! scene's values), and its validation. The C ABI's `WetHairSimDesc` is converted into this.

use crate::error::{check_finite3, check_non_negative, check_positive, invalid, Error, Result};
use crate::physics::collide::Shape;
use crate::physics::spring::DampingModel;
use glam::Vec3;

mod fixed;
mod guides;
mod volume;
mod wet;
pub use fixed::{FixedStep, MAX_STEPS_PER_ADVANCE};
pub use guides::{GuideChoice, Guides};
pub use volume::Volume;
pub use wet::{HeldWater, Wind};

/// Most substeps per step.
pub const MAX_SUBSTEPS: u32 = 1024;
/// Most worker threads per simulation.
pub const MAX_THREADS: u32 = 256;
/// Most colliders per simulation.
pub const MAX_COLLIDERS: usize = 64;
/// Smallest water influence radius `r_max`, m (a micrometre: below it the grid's cells
/// would be finer than anything a hair simulation resolves).
pub const MIN_R_MAX: f32 = 1.0e-6;
/// Largest water influence radius `r_max`, m.
pub const MAX_R_MAX: f32 = 10.0;
/// Most water particles one simulation may hold.
pub const MAX_WATER_CAPACITY: u32 = 1 << 22;

/// How each substep advances the strands (`WetHairSimDesc::integrator`); exported as
/// `WetHairIntegrator`. One definition for Rust and C: the variants are the C constants'
/// names without their prefix.
/// cbindgen:rename-all=prefix:WETHAIR_INTEGRATOR_
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
#[allow(non_camel_case_types)]
pub enum Integrator {
    /// The paper's symplectic (semi-implicit) Euler: cheapest; stable only while
    /// `h² λ + 2 h γ < 4` (λ, γ: largest stiffness and damping rates).
    SYMPLECTIC_EULER = 0,
    /// Linearised backward Euler with a banded direct solve per strand: unconditionally stable
    /// for the springs, damps high frequencies; adhesion and collisions stay explicit.
    IMPLICIT_EULER = 1,
    /// XPBD with small steps: springs become compliant distance constraints (compliance 1/k),
    /// one Gauss-Seidel sweep per substep; stiff springs act as inextensible ones.
    XPBD = 2,
    /// Symplectic Euler when it is stable for the scene's stiffness, masses and substep
    /// (with a 10% margin), else implicit Euler; resolved at create. Under an error budget
    /// ([`SimParams::tolerance`]) it starts with BDF2 instead of implicit Euler and moves
    /// between symplectic Euler and BDF2 frame by frame, whichever keeps the error under the
    /// tolerance at the least cost (`sim/auto.rs`; [`crate::Stats::integrator`] says which).
    AUTO = 3,
    /// BDF2 on implicit Euler's solver: a backward Euler solve from the blend of this substep's
    /// start and the one before (`physics/bdf2.rs`), so second order in the springs at the cost
    /// of implicit Euler, and as stable (give it 3 Newton iterations where springs are far
    /// past the explicit limit). The first substep, the first after a reset, and a jump in
    /// the frame time that could grow the history's errors past 2x (`Bdf2Clock`) take a
    /// backward Euler step.
    BDF2 = 4,
}

impl Integrator {
    /// Whether the springs are solved implicitly (implicit Euler's banded Newton solve, which
    /// BDF2 runs from its blended start).
    pub fn is_implicit(self) -> bool {
        matches!(self, Integrator::IMPLICIT_EULER | Integrator::BDF2)
    }
}

/// The stability measure of symplectic Euler at one free point of mass `m` whose stiffest
/// stretch and bend springs are `stretch` and `bend`, for substep `h`: `h² λ + 2 h γ`, stable
/// below 4. `λ ≈ 4 k_s / m` is the largest eigenvalue of K/M for a chain (bend springs add
/// `16 (k_b - k_s/4) / m` only when `k_b > k_s / 4`), and `γ` the same for the dampers.
pub fn explicit_limit(stretch: SpringParams, bend: SpringParams, m: f32, h: f32) -> f32 {
    let (lambda, gamma) = explicit_rates(stretch, bend, m);
    h * h * lambda + 2.0 * h * gamma
}

/// `(λ, γ)` of [`explicit_limit`]: the stiffness and damping rates, 1/s² and 1/s.
pub fn explicit_rates(stretch: SpringParams, bend: SpringParams, m: f32) -> (f32, f32) {
    let rate = |ks: f32, kb: f32| (4.0 * ks + 16.0 * (kb - 0.25 * ks).max(0.0)) / m;
    (
        rate(stretch.stiffness, bend.stiffness),
        rate(stretch.damping, bend.damping),
    )
}

/// How each spring's stiffness and damping follow from the parameters
/// (`WetHairSimDesc::spring_model`); exported as `WetHairSpringModel`.
/// cbindgen:rename-all=prefix:WETHAIR_SPRING_MODEL_
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
#[allow(non_camel_case_types)]
pub enum SpringModel {
    /// Every spring of a family has the same k and c ([`SimParams::stretch`],
    /// [`SimParams::bend`]): the paper's model. How stiff a strand is then depends on how finely
    /// it is sampled (more, shorter segments in series stretch more).
    PER_SPRING = 0,
    /// Springs follow from material properties ([`SimParams::material`]) and their rest
    /// length: stretch `k = EA / l`, bend `k = EI / L³` (L the rest span of the i, i+2 spring),
    /// dampers the same way, so a strand sags the same however finely it is sampled
    /// (docs/METHOD.md, "Material parameters").
    MATERIAL = 1,
}

/// Material properties of a strand, from which [`SpringModel::MATERIAL`] derives each spring.
/// The paper scene is `EA = 40 N/m × 0.02 m = 0.8 N` and `EI = 10 N/m × (0.04 m)³ =
/// 6.4e-4 N·m²` (its springs then come out at its 40 and 10 N/m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialParams {
    /// Axial stiffness EA, N: a stretch spring of rest length l gets `k = EA / l`.
    pub stretch_modulus: f32,
    /// Axial damping, N·s: a stretch spring gets `c = stretch_damping / l`.
    pub stretch_damping: f32,
    /// Bending stiffness EI, N·m²: a bend spring of rest span L gets `k = EI / L³`.
    pub bend_modulus: f32,
    /// Bending damping, N·m²·s: a bend spring gets `c = bend_damping / L³`.
    pub bend_damping: f32,
}

impl MaterialParams {
    /// The paper scene's springs as material properties (exact at its 0.02 m segments).
    pub const PAPER: MaterialParams = MaterialParams {
        stretch_modulus: 0.8,
        stretch_damping: 4.0e-4,
        bend_modulus: 6.4e-4,
        bend_damping: 3.2e-7,
    };

    /// Hair-like defaults for a simulated strand that stands for a wisp of about 150 fibres
    /// (docs/METHOD.md): stiff enough that a 0.4 m strand of 1 g/m stretches 0.5% under its
    /// own weight, and a bending length `(EI / (ρ g))^(1/3)` of 5 cm at 1 g/m, so hair hangs
    /// and sways instead of standing out like wire.
    pub const HAIR: MaterialParams = MaterialParams {
        stretch_modulus: 0.8,
        stretch_damping: 4.0e-4,
        bend_modulus: 1.2e-6,
        bend_damping: 6.0e-10,
    };
}

/// Largest material property (any unit): with [`MIN_MATERIAL_LENGTH`] it keeps every derived
/// spring constant finite in f32 (`1e20 / (1e-4)³ = 1e32`).
pub const MAX_MATERIAL: f32 = 1.0e20;

/// Shortest spring length the material law divides by, m: shorter segments (a welded file
/// removes them, a host's own arrays may keep them) get the stiffness of one this long, so a
/// near-zero segment cannot make a spring infinitely stiff.
pub const MIN_MATERIAL_LENGTH: f32 = 1.0e-4;

/// Where the step runs (`WetHairSimDesc::backend`); exported as `WetHairBackend`.
/// cbindgen:rename-all=prefix:WETHAIR_BACKEND_
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
#[allow(non_camel_case_types)]
pub enum Backend {
    /// A hardware GPU when one is found and runs the scene's integrator, else the CPU. A
    /// software adapter (Mesa's lavapipe) is skipped: it is slower than the CPU backend. The
    /// backend info (`wethair_sim_get_backend_info`) says which was chosen and why.
    AUTO = 0,
    /// The multi-threaded CPU backend (the reference).
    CPU = 1,
    /// The wgpu compute backend on any adapter, software ones included; an error when none.
    GPU = 2,
}

/// How the vertices reach host memory on the GPU backend (`WetHairSimDesc::readback`; the
/// CPU backend always has them); exported as `WetHairReadback`.
/// cbindgen:rename-all=prefix:WETHAIR_READBACK_
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
#[allow(non_camel_case_types)]
pub enum Readback {
    /// A read waits for the step just submitted and returns its vertices.
    LATEST = 0,
    /// Each step also copies its vertices to one of two staging buffers; a read returns the
    /// step before the last one, which is long finished, so the host never waits on the GPU.
    /// The first read waits.
    PREVIOUS_FRAME = 1,
}

/// Stiffness and damping of one spring family.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpringParams {
    /// Stiffness k, N/m. 0 removes the family (and its pass).
    pub stiffness: f32,
    /// Damping c, N·s/m.
    pub damping: f32,
}

/// Water particles and their pull on hair (METHOD.md eq. 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterParams {
    /// Particle radius `r_min`, m: hair settles on this shell.
    pub r_min: f32,
    /// Influence radius `r_max`, m (> `r_min`): no pull beyond it.
    pub r_max: f32,
    /// Adhesion strength `s`, N: the peak pull between one particle and one hair point, or
    /// between one particle and `adhesion_length` m of hair.
    pub adhesion: f32,
    /// The length of hair `adhesion` is quoted over, m, 0..=1: a point pulls with
    /// `s ℓ / L`, `ℓ` half of each rest segment it ends, so a drop pulls a strand alike
    /// however finely it is sampled (`physics/per_length.rs`). 0: every point pulls with `s`
    /// (the paper's, and [`SimParams::paper`]'s); [`SimParams::default`]:
    /// [`crate::physics::per_length::DEFAULT_LENGTH`].
    pub adhesion_length: f32,
    /// Mass of one particle, kg.
    pub particle_mass: f32,
    /// Linear drag on particles, N·s/m.
    pub drag: f32,
    /// Most particles the simulation holds; adding more is an error. Buffers for them are
    /// allocated at the first add, never in the step.
    pub capacity: u32,
    /// How fast a hair point near water becomes wet (1/s): wetness w in [0, 1] follows
    /// `w += (1 - w) min(1, rate h)` while a particle is within `r_max`.
    pub wetting_rate: f32,
    /// Particles farther than this (m) from the groom's centre (moved with the head) are
    /// removed at the end of a step. 0 picks half the groom's diagonal plus its longest strand.
    pub domain_radius: f32,
    /// Drops that meet coalesce, m: at each step's start the drops whose positions fall in
    /// one cell of this side take their mean position and velocity (the centre of mass and
    /// the momentum are kept) and from then on pull as one source of eq. 2 with their summed
    /// strength, each taking an equal share of its reaction (`cpu/piles.rs`). The host still
    /// sees every drop. 0 (the default): drops pass through each other, as in the paper. At
    /// most `(r_max − r_min) / 8`. The paper's model only (with held water each particle
    /// carries its own water, and this is ignored); both backends (the GPU's `piles.wgsl`).
    pub pile_cell: f32,
}

/// Which per-vertex attributes the host wants, as bits; each present one is written, in this
/// order, interleaved per vertex as f32.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexAttributes(pub u32);

impl VertexAttributes {
    /// Position, 3 floats, m.
    pub const POSITION: u32 = 1;
    /// Unit tangent along the strand, 3 floats.
    pub const TANGENT: u32 = 2;
    /// Wetness in [0, 1], 1 float.
    pub const WETNESS: u32 = 4;
    /// Every attribute this version knows.
    pub const ALL: u32 = 7;

    /// Floats per vertex.
    pub fn stride(self) -> usize {
        let b = self.0;
        3 * (b & 1) as usize + 3 * ((b >> 1) & 1) as usize + ((b >> 2) & 1) as usize
    }

    /// Float offset of an attribute bit within a vertex, if present.
    pub fn offset(self, bit: u32) -> Option<usize> {
        if self.0 & bit == 0 {
            return None;
        }
        let below = self.0 & (bit - 1);
        Some(VertexAttributes(below).stride())
    }
}

/// Everything that defines a simulation apart from the groom.
#[derive(Clone, Debug, PartialEq)]
pub struct SimParams {
    /// Stretch springs (i, i+1).
    pub stretch: SpringParams,
    /// Bend springs (i, i+2).
    pub bend: SpringParams,
    /// Whether springs come from `stretch`/`bend` as given or from `material`.
    pub spring_model: SpringModel,
    /// Material properties ([`SpringModel::MATERIAL`]).
    pub material: MaterialParams,
    /// Which velocity the spring dampers act on.
    pub damping_model: DampingModel,
    /// Gravity, m/s².
    pub gravity: Vec3,
    /// Linear air drag on hair points, N·s/m: on every point as given when `air_drag_length`
    /// is 0, else on each `air_drag_length` m of hair (`physics/per_length.rs`).
    pub air_drag: f32,
    /// The length of hair `air_drag` is quoted over, m, 0..=1: a point takes `air_drag ℓ / L`,
    /// `ℓ` half of each rest segment it ends, so a strand feels the same drag however finely it
    /// is sampled. 0: every point takes `air_drag` (the paper's, and [`SimParams::paper`]'s);
    /// [`SimParams::default`]: [`crate::physics::per_length::DEFAULT_LENGTH`].
    pub air_drag_length: f32,
    /// Substeps per [`crate::Simulation::step`] (the paper: 4).
    pub substeps: u32,
    /// How each substep advances the strands.
    pub integrator: Integrator,
    /// Newton iterations of implicit Euler (1 = linearised) or constraint sweeps of XPBD per
    /// substep; symplectic Euler ignores it.
    pub solver_iterations: u32,
    /// Worker threads; 0 uses every core.
    pub threads: u32,
    /// Water particles.
    pub water: WaterParams,
    /// Spheres and capsules: in head space, following the head transform, or, where
    /// `collider_frames` is given, each in its own frame.
    pub colliders: Vec<Shape>,
    /// Colliders on bones of their own (empty, the default: every collider follows the
    /// head). Else one frame per collider, its frame to the world at the start (a rotation, a
    /// translation and a uniform scale): the collider's points are in that frame, and
    /// [`crate::Simulation::set_collider_transform`] moves it each step, as the host's
    /// skeleton moves a shoulder or a collar under long hair.
    pub collider_frames: Vec<glam::Affine3A>,
    /// Signed distance field colliders, each placed by its own transform
    /// ([`crate::Simulation::set_sdf_transform`]); at most [`crate::physics::sdf::MAX_SDFS`].
    /// Shared, not copied, when parameters are cloned.
    pub sdfs: Vec<std::sync::Arc<crate::physics::sdf::Sdf>>,
    /// Tangential velocity lost on collider contact, 0..=1.
    pub friction: f32,
    /// Vertex attributes written for the host.
    pub attributes: VertexAttributes,
    /// Where the step runs.
    pub backend: Backend,
    /// How vertices reach host memory on the GPU backend.
    pub readback: Readback,
    /// Water held by the hair and what it does: weight, limpness, absorption, bridges, flow,
    /// drip and drying (off: the paper's model).
    pub held_water: HeldWater,
    /// The wind blowing past hair and particles (calm by default); changeable every frame
    /// through [`crate::Simulation::set_wind`].
    pub wind: Wind,
    /// The live error estimate ([`crate::Stats::error_estimate`]): 0 leaves it out (the
    /// default); N > 0 runs every N-th strand a second time, on the CPU at twice the substeps,
    /// and extrapolates the difference (`sim/estimate.rs`). Its cost is about `2 T / N` of a
    /// step on T threads (128 on 2 threads: 3.5% measured with BDF2, `benches/frame.rs`
    /// `estimate`; 1: the whole groom again, twice over).
    pub error_estimate_stride: u32,
    /// An error budget, m (0: off, the default): after each step the simulation doubles its
    /// substeps while the estimate's largest point error exceeds this, and halves them while
    /// even half as many would keep it below half of it (`sim/budget.rs`); with
    /// [`Integrator::AUTO`] it also picks symplectic Euler or BDF2 (`sim/auto.rs`). Uses the
    /// estimate (every [`DEFAULT_BUDGET_STRIDE`]-th strand when `error_estimate_stride` is 0).
    pub tolerance: f32,
    /// The most substeps the budget may choose (at least `substeps`, at most half of
    /// [`MAX_SUBSTEPS`], the estimate's shadow running twice as many).
    pub max_substeps: u32,
    /// Fixed-step updates for [`crate::Simulation::advance`] (off by default).
    pub fixed_step: FixedStep,
    /// Roots on a skinned mesh (off by default): each strand's pinned points follow the root
    /// frame set by [`crate::Simulation::set_root_frames`] instead of the head transform
    /// (`physics/roots.rs`).
    pub skinned_roots: bool,
    /// A root that moves farther than this in one step teleports its strand (carried rigidly,
    /// velocities zeroed) instead of sweeping it, m; 0: never. Skinned roots only.
    pub root_teleport_distance: f32,
    /// Hair-hair volume: density pressure and friction over a grid (off by default;
    /// docs/VOLUME.md).
    pub volume: Volume,
    /// Guides and followers with level of detail (off by default: every strand simulated;
    /// docs/GUIDES.md).
    pub guides: Guides,
}

/// The estimate's stride an error budget uses when the host set none.
pub const DEFAULT_BUDGET_STRIDE: u32 = 128;

impl SimParams {
    /// Each hair point's air drag: `air_drag` on every point, or quoted over `air_drag_length`
    /// of hair.
    pub fn hair_drag(&self) -> crate::physics::per_length::PerLength {
        crate::physics::per_length::PerLength::new(self.air_drag, self.air_drag_length)
    }

    /// Each hair point's share of eq. 2's pull: 1, or the hair it stands for over
    /// `water.adhesion_length`.
    pub fn adhesion_share(&self) -> crate::physics::per_length::PerLength {
        crate::physics::per_length::PerLength::new(1.0, self.water.adhesion_length)
    }

    /// Whether drops that meet coalesce (`water.pile_cell`): a cell is set and the scene runs
    /// the paper's model (with held water each particle carries its own water, and the cell
    /// is ignored).
    pub fn coalesces(&self) -> bool {
        self.water.pile_cell > 0.0 && !self.held_water.enabled
    }

    /// The strand stride of the error estimate: the host's, or the budget's default when a
    /// tolerance is set without one (0: no estimate).
    pub fn estimate_stride(&self) -> u32 {
        match (self.error_estimate_stride, self.tolerance > 0.0) {
            (0, true) => DEFAULT_BUDGET_STRIDE,
            (n, _) => n,
        }
    }
}

impl Default for SimParams {
    /// What a groom from a file or a host should start from: springs from hair-like material
    /// properties ([`MaterialParams::HAIR`], so any sampling behaves the same) and
    /// [`Integrator::AUTO`] (real grooms' short, light segments are too stiff for symplectic
    /// Euler at a 60 Hz frame; the paper scene still gets it). Everything else as
    /// [`SimParams::paper`].
    fn default() -> Self {
        SimParams {
            spring_model: SpringModel::MATERIAL,
            material: MaterialParams::HAIR,
            integrator: Integrator::AUTO,
            air_drag_length: crate::physics::per_length::DEFAULT_LENGTH,
            water: WaterParams {
                adhesion_length: crate::physics::per_length::DEFAULT_LENGTH,
                ..SimParams::paper().water
            },
            ..SimParams::paper()
        }
    }
}

impl SimParams {
    /// The paper scene's parameters exactly: the same k and c for every spring, symplectic
    /// Euler, 4 substeps, no collider.
    pub fn paper() -> Self {
        SimParams {
            stretch: SpringParams {
                stiffness: 40.0,
                damping: 0.02,
            },
            bend: SpringParams {
                stiffness: 10.0,
                damping: 0.005,
            },
            spring_model: SpringModel::PER_SPRING,
            material: MaterialParams::PAPER,
            damping_model: DampingModel::AXIAL,
            gravity: Vec3::new(0.0, 0.0, -9.81),
            air_drag: 0.0,
            air_drag_length: 0.0,
            substeps: 4,
            integrator: Integrator::SYMPLECTIC_EULER,
            solver_iterations: 1,
            threads: 0,
            water: WaterParams {
                r_min: 0.002,
                r_max: 0.008,
                adhesion: 0.008,
                adhesion_length: 0.0,
                particle_mass: 1.0e-3,
                drag: 2.0e-3,
                capacity: 65_536,
                wetting_rate: 20.0,
                domain_radius: 0.0,
                pile_cell: 0.0,
            },
            colliders: Vec::new(),
            collider_frames: Vec::new(),
            sdfs: Vec::new(),
            skinned_roots: false,
            root_teleport_distance: crate::physics::roots::TELEPORT_DISTANCE,
            volume: Volume::OFF,
            guides: Guides::ALL,
            friction: 0.2,
            attributes: VertexAttributes(
                VertexAttributes::POSITION | VertexAttributes::TANGENT | VertexAttributes::WETNESS,
            ),
            backend: Backend::AUTO,
            readback: Readback::LATEST,
            held_water: HeldWater::OFF,
            wind: Wind::CALM,
            error_estimate_stride: 0,
            tolerance: 0.0,
            max_substeps: 64,
            fixed_step: FixedStep::OFF,
        }
    }

    /// The paper scene with its head as a sphere collider (radius 0.1 m at the origin).
    pub fn paper_scene_with_head() -> Self {
        SimParams {
            colliders: vec![Shape::Sphere {
                center: Vec3::ZERO,
                radius: 0.1,
            }],
            ..SimParams::paper()
        }
    }

    /// Checks every field; the error names the first bad one.
    pub fn validate(&self) -> Result<()> {
        self.held_water.validate(&self.water)?;
        self.wind.validate()?;
        self.fixed_step.validate()?;
        check_non_negative("stretch stiffness", self.stretch.stiffness)?;
        check_non_negative("stretch damping", self.stretch.damping)?;
        check_non_negative("bend stiffness", self.bend.stiffness)?;
        check_non_negative("bend damping", self.bend.damping)?;
        let m = &self.material;
        for (name, v) in [
            ("material stretch_modulus", m.stretch_modulus),
            ("material stretch_damping", m.stretch_damping),
            ("material bend_modulus", m.bend_modulus),
            ("material bend_damping", m.bend_damping),
        ] {
            if !(v.is_finite() && (0.0..=MAX_MATERIAL).contains(&v)) {
                return Err(invalid!("{name} must be in [0, {MAX_MATERIAL:e}], got {v}"));
            }
        }
        check_finite3("gravity", self.gravity.to_array())?;
        check_non_negative("air drag", self.air_drag)?;
        crate::physics::per_length::check_length("air_drag_length", self.air_drag_length)?;
        if self.substeps == 0 || self.substeps > MAX_SUBSTEPS {
            return Err(invalid!("substeps must be 1..={MAX_SUBSTEPS}, got {}", self.substeps));
        }
        check_non_negative("tolerance", self.tolerance)?;
        if self.tolerance > 0.0 && !(self.substeps..=MAX_SUBSTEPS / 2).contains(&self.max_substeps) {
            return Err(invalid!(
                "max_substeps must be {}..={} with a tolerance, got {}",
                self.substeps,
                MAX_SUBSTEPS / 2,
                self.max_substeps
            ));
        }
        if self.solver_iterations == 0 || self.solver_iterations > 64 {
            return Err(invalid!(
                "solver_iterations must be 1..=64, got {}",
                self.solver_iterations
            ));
        }
        if self.threads > MAX_THREADS {
            return Err(invalid!("threads must be 0..={MAX_THREADS}, got {}", self.threads));
        }
        let w = &self.water;
        check_non_negative("water r_min", w.r_min)?;
        if !(w.r_max.is_finite() && (MIN_R_MAX..=MAX_R_MAX).contains(&w.r_max)) {
            return Err(invalid!(
                "water r_max must be in [{MIN_R_MAX}, {MAX_R_MAX}] m, got {}",
                w.r_max
            ));
        }
        if w.r_max <= w.r_min {
            return Err(invalid!("water r_max ({}) must exceed r_min ({})", w.r_max, w.r_min));
        }
        check_non_negative("water adhesion", w.adhesion)?;
        crate::physics::per_length::check_length("water adhesion_length", w.adhesion_length)?;
        check_positive("water particle mass", w.particle_mass)?;
        check_non_negative("water drag", w.drag)?;
        check_non_negative("water wetting rate", w.wetting_rate)?;
        check_non_negative("water domain radius", w.domain_radius)?;
        check_non_negative("water pile cell", w.pile_cell)?;
        if w.pile_cell > (w.r_max - w.r_min) / 8.0 {
            return Err(invalid!(
                "water pile_cell ({}) must be at most (r_max - r_min) / 8 = {} m",
                w.pile_cell,
                (w.r_max - w.r_min) / 8.0
            ));
        }
        if w.capacity > MAX_WATER_CAPACITY {
            return Err(Error::Capacity(format!(
                "water capacity {} exceeds {MAX_WATER_CAPACITY}",
                w.capacity
            )));
        }
        if self.colliders.len() > MAX_COLLIDERS {
            return Err(Error::Capacity(format!(
                "{} colliders, at most {MAX_COLLIDERS}",
                self.colliders.len()
            )));
        }
        for (i, c) in self.colliders.iter().enumerate() {
            let (pts, r) = match *c {
                Shape::Sphere { center, radius } => ([center, center], radius),
                Shape::Capsule { a, b, radius } => ([a, b], radius),
            };
            check_finite3(&format!("collider {i} point"), pts[0].to_array())?;
            check_finite3(&format!("collider {i} point"), pts[1].to_array())?;
            check_positive(&format!("collider {i} radius"), r)?;
        }
        if !self.collider_frames.is_empty() && self.collider_frames.len() != self.colliders.len() {
            return Err(invalid!(
                "{} collider frames for {} colliders: give one per collider, or none",
                self.collider_frames.len(),
                self.colliders.len()
            ));
        }
        for (i, t) in self.collider_frames.iter().enumerate() {
            crate::physics::frames::check_transform(t, &format!("collider {i}'s frame"))?;
        }
        if self.sdfs.len() > crate::physics::sdf::MAX_SDFS {
            return Err(Error::Capacity(format!(
                "{} SDF colliders, at most {}",
                self.sdfs.len(),
                crate::physics::sdf::MAX_SDFS
            )));
        }
        for (i, s) in self.sdfs.iter().enumerate() {
            s.validate(&format!("SDF {i}"))?;
        }
        self.volume.validate()?;
        self.guides.validate()?;
        if !(self.root_teleport_distance.is_finite() && self.root_teleport_distance >= 0.0) {
            return Err(invalid!(
                "root_teleport_distance must be finite and >= 0 m, got {}",
                self.root_teleport_distance
            ));
        }
        if !(self.friction.is_finite() && (0.0..=1.0).contains(&self.friction)) {
            return Err(invalid!("friction must be in [0, 1], got {}", self.friction));
        }
        let a = self.attributes.0;
        if a == 0 || a & !VertexAttributes::ALL != 0 {
            return Err(invalid!("vertex attributes 0x{a:x}: need a non-empty subset of 0x7"));
        }
        Ok(())
    }
}
