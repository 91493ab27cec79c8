//! The plain-old-data records the GPU passes read (their WGSL twins are generated from these
//! declarations by `gpu/wgsl.rs`), the word layouts of the status and grid buffers, and the
//! helpers that create buffers.

use super::wgsl::gpu_record;

gpu_record! {
    /// Per-step constants (WGSL `Params`, a uniform).
    pub struct Params {
        /// Substep, s.
        pub h: f32,
        /// 1 / substep, computed on the host as the CPU backend does.
        pub inv_h: f32,
        /// Air drag on every hair point, N·s/m (`PerLength::per_point`; 0 where `drag_scale` is
        /// set).
        pub drag: f32,
        /// Collider friction.
        pub friction: f32,
        /// Gravity (xyz), m/s².
        pub g: [f32; 4],
        /// Hair points.
        pub points: u32,
        /// Strands.
        pub strands: u32,
        /// Eq. 2's r_min.
        pub r_min: f32,
        /// Eq. 2's r_max.
        pub r_max: f32,
        /// Eq. 2's s.
        pub adhesion: f32,
        /// Wetting per substep, min(rate h, 1).
        pub wet_gain: f32,
        /// 1 / particle mass.
        pub particle_inv_mass: f32,
        /// A particle's drag rate, `drag / particle_mass`, 1/s (as the CPU computes it): every
        /// drop, whatever its water, slows at a full particle's rate.
        pub water_drag_rate: f32,
        /// Particle capacity.
        pub capacity: u32,
        /// Floats per vertex.
        pub stride: u32,
        /// Position offset in floats, or `u32::MAX`.
        pub pos_off: u32,
        /// Tangent offset, or `u32::MAX`.
        pub tan_off: u32,
        /// Wetness offset, or `u32::MAX`.
        pub wet_off: u32,
        /// Particles waiting in the incoming buffer.
        pub incoming: u32,
        /// Most buckets of the water's hashed grid (for its capacity).
        pub max_buckets: u32,
        /// Squared domain radius, m².
        pub domain_r2: f32,
        /// Domain centre (xyz), placed by this step's final head transform.
        pub domain_center: [f32; 4],
        /// The wind this step (xyz), m/s: drag pulls hair and particles toward it.
        pub wind: [f32; 4],
        /// The whole step, s (held water's once-per-step passes).
        pub dt: f32,
        /// Held water's drying time constant in still air, s (0: never dries).
        pub dry_time: f32,
        /// Air speed at which held water dries twice as fast, m/s.
        pub dry_air_speed: f32,
        /// Bending stiffness of saturated hair over dry.
        pub wet_bend_ratio: f32,
        /// 1 when each particle carries its own water (held water), else 0.
        pub massive: u32,
        /// Air drag per metre of a point's two rest segments summed, N·s/m² (`PerLength::scale`;
        /// 0: `drag` on every point).
        pub drag_scale: f32,
        /// How fast held water above the hold limit runs down a vertical strand, m/s
        /// (`HeldWater::flow_speed`; 0: no flow).
        pub flow_speed: f32,
        /// The smallest drop that leaves a point, quanta.
        pub min_drop: u32,
        /// 1 when hair points draw in the particles they reach (absorption), else 0.
        pub absorbs: u32,
        /// The fraction of a particle a point standing for `wet::ABSORB_LENGTH` of hair may ask
        /// for in a substep, `1 - e^(-rate h)` (`absorb_take_at` scales it to the point's share).
        pub absorb_take: f32,
        /// Eq. 2's strength per quantum a particle holds, N (with absorption).
        pub strength_per_quantum: f32,
        /// A particle left with fewer quanta goes whole to the point that asked it for most.
        pub absorb_last: u32,
        /// Liquid bridges: their length `d_b`, m (0 without bridges).
        pub bridge_length: f32,
        /// Liquid bridges: their tension `kappa`, N/m.
        pub bridge_tension: f32,
        /// Liquid bridges: this step's search turn (`wet::bridge_search_turn`).
        pub bridge_turn: u32,
        /// Liquid bridges: the word of the bridge buffer where the points' masks of mutual
        /// bridges start, after every point's record (`bridge_words`; 0 without bridges).
        pub bridge_masks: u32,
        /// Eq. 2's share per metre of a point's two rest segments summed, 1/m
        /// (`SimParams::adhesion_share`'s `PerLength::scale`; 0: every point pulls alike).
        pub adhesion_scale: f32,
        /// Eq. 2's stability limit: the substep's `h²` times the profile's steepest slope
        /// (`physics/pull_limit.rs` `PullLimit::slope_h2`).
        pub pull_slope_h2: f32,
        /// Eq. 2's stability limit: how many candidate particles a point may have with no
        /// need to count them (`PullLimit::free`; 0: every point counts), for particles of one
        /// drop each (a point divides it by the largest pile, `grid_header::PILE_MAX`).
        pub pull_free: u32,
        /// Drops that meet coalesce in cells of this side, m (`SimParams::coalesces`; 0: off).
        pub pile_cell: f32,
        /// 1 / `pile_cell`, as the CPU computes it.
        pub pile_inv_cell: f32,
        /// The fixed-point unit of a drop's offset in its pile cell, m (`pile_cell` times
        /// `cpu/piles.rs`'s `POSITION_UNIT`).
        pub pile_unit: f32,
        /// 1 / `pile_unit`, as the CPU computes it.
        pub pile_inv_unit: f32,
        /// Padding (a uniform's size is a multiple of 16 bytes).
        pub pad0: u32,
    }
}

gpu_record! {
    /// One SDF collider placed for a substep (WGSL `Sdf`; `physics/sdf.rs` `PlacedSdf` and the
    /// grid's shape): the world-to-grid rows, the grid-to-world linear rows (normals), the
    /// world box, and where its samples start.
    pub struct SdfGpu {
        /// World to grid frame, row x (xyz; w the translation).
        pub gx: [f32; 4],
        /// Row y.
        pub gy: [f32; 4],
        /// Row z.
        pub gz: [f32; 4],
        /// Grid frame to world, linear part, row x (xyz; w unused).
        pub wx: [f32; 4],
        /// Row y.
        pub wy: [f32; 4],
        /// Row z.
        pub wz: [f32; 4],
        /// World box's lower corner (xyz); w the transform's uniform scale.
        pub lo: [f32; 4],
        /// World box's upper corner (xyz); w the grid's cell, m.
        pub hi: [f32; 4],
        /// The grid's first sample in its frame (xyz); w unused.
        pub origin: [f32; 4],
        /// Samples along x, y, z; w where the grid's samples start in the values buffer.
        pub dims: [u32; 4],
        /// The surface's velocity field (`PlacedSdf::velocity`), row x (xyz; w the
        /// translation): a point fixed to the grid at `p` moves at `(dot(vx.xyz, p) + vx.w, …)`.
        pub vx: [f32; 4],
        /// Row y.
        pub vy: [f32; 4],
        /// Row z.
        pub vz: [f32; 4],
    }
}

gpu_record! {
    /// One strand's root frames at the start and the end of the step (WGSL `RootPair`;
    /// `physics/roots.rs` `RootFrame`): positions (w unused) and rotations (x y z w).
    pub struct RootPairGpu {
        /// Where the root is at the step's start.
        pub from_pos: [f32; 4],
        /// Its rotation at the start.
        pub from_rot: [f32; 4],
        /// Where the root is at the step's end.
        pub to_pos: [f32; 4],
        /// Its rotation at the end.
        pub to_rot: [f32; 4],
    }
}

gpu_record! {
    /// One pinned point of a scene with skinned roots (WGSL `Pin`): its rest offset from its
    /// strand's root, and which point and strand it is.
    pub struct PinGpu {
        /// Rest position minus the root's (xyz, head space); w unused.
        pub offset: [f32; 4],
        /// x the point, y the strand; z, w unused.
        pub at: [u32; 4],
    }
}

gpu_record! {
    /// One strand carried rigidly between root frames (WGSL `Carry`: a teleport or a reset).
    pub struct CarryGpu {
        /// The frame the strand leaves.
        pub from_pos: [f32; 4],
        /// Its rotation.
        pub from_rot: [f32; 4],
        /// The frame the strand lands on.
        pub to_pos: [f32; 4],
        /// Its rotation.
        pub to_rot: [f32; 4],
        /// x the strand's first point, y its last; z, w unused.
        pub span: [u32; 4],
    }
}

gpu_record! {
    /// The roots passes' uniform (WGSL `RootsUniform`), one per substep and one for carries.
    pub struct RootsUniformGpu {
        /// How far through the step this substep ends, 0..=1.
        pub a: f32,
        /// Strands to carry (the carry slot only).
        pub count: u32,
        /// Unused: rounds the record to WGSL's 16-byte uniform size.
        pub pad0: u32,
        /// Unused.
        pub pad1: u32,
    }
}

gpu_record! {
    /// Hair-hair volume's step (WGSL `VolumeStep`, a uniform; `physics/volume.rs`): world to
    /// head space, head-space gradients to world ones, the grid, and the law.
    pub struct VolumeStepGpu {
        /// World to head space, row x (xyz; w the translation).
        pub hx: [f32; 4],
        /// Row y.
        pub hy: [f32; 4],
        /// Row z.
        pub hz: [f32; 4],
        /// Head-space gradient to world (the head's inverse transpose), row x (w unused).
        pub wx: [f32; 4],
        /// Row y.
        pub wy: [f32; 4],
        /// Row z.
        pub wz: [f32; 4],
        /// The grid's first sample (xyz); w its cell, m.
        pub origin: [f32; 4],
        /// Samples along x, y, z; w the hair points.
        pub dims: [u32; 4],
        /// The friction's blend, the pressure's push, the rest density, and the density of one
        /// mass quantum in a cell (kg/m³).
        pub law: [f32; 4],
    }
}

gpu_record! {
    /// The output blend (WGSL `Blend`, a uniform; fixed steps with interpolation only).
    pub struct BlendGpu {
        /// How far the output moves from the kept positions toward the state, 0..=1.
        pub a: f32,
        /// Unused: rounds the record to WGSL's 16-byte uniform size.
        pub pad0: u32,
        /// Unused.
        pub pad1: u32,
        /// Unused.
        pub pad2: u32,
    }
}

gpu_record! {
    /// The followers' output pose (WGSL `FollowUniform`, a uniform; scenes with guides only).
    pub struct FollowUniformGpu {
        /// The head's rotation (a unit quaternion, xyzw) the offsets turn with.
        pub head: [f32; 4],
        /// How far the output has moved from the old bindings to the new, 0..=1.
        pub blend: f32,
        /// `Guides::clump`.
        pub clump: f32,
        /// Host vertices.
        pub host_points: u32,
        /// 1 while old bindings exist to blend from.
        pub has_from: u32,
        /// 1 while the fixed steps' output blend is on (guides read kept positions moved by
        /// `kept_a`).
        pub kept: u32,
        /// The fixed steps' blend factor.
        pub kept_a: f32,
        /// Guides pass `guide_frames` gathers (those the backend steps).
        pub guides: u32,
        /// 1 with skinned roots: each guide's frames start from its own root's rotation, and
        /// each strand's root points land on its own frame (`follow_roots`).
        pub roots: u32,
    }
}

gpu_record! {
    /// How one host strand follows the guides (WGSL `FollowStrand`; physics/followers.rs
    /// `Follow`, now and before the last change of the simulated fraction).
    pub struct FollowStrandGpu {
        /// The strand's first host vertex.
        pub first: u32,
        /// Its points.
        pub count: u32,
        /// Skinned roots: its root points (`Followers::root_points`); else 0.
        pub root_points: u32,
        /// Unused.
        pub pad1: u32,
        /// Guides (xyz; w unused).
        pub guides: [u32; 4],
        /// Their weights.
        pub weights: [f32; 4],
        /// The guides before the last change.
        pub from_guides: [u32; 4],
        /// Their weights.
        pub from_weights: [f32; 4],
    }
}

gpu_record! {
    /// Constant data of one hair point (WGSL `Point`).
    pub struct PointGpu {
        /// Rest position in head space.
        pub rest: [f32; 3],
        /// 1 / mass, 0 when pinned.
        pub inv_mass: f32,
        /// Rest length to the next point.
        pub rest_stretch: f32,
        /// Rest length to the point after next.
        pub rest_bend: f32,
        /// The strand's first point.
        pub first: u32,
        /// The strand's last point.
        pub last: u32,
        /// Stiffness of the spring to the next point, N/m (`plan::point_springs`).
        pub stretch_k: f32,
        /// Damping of the spring to the next point, N·s/m.
        pub stretch_c: f32,
        /// Stiffness of the spring to the point after next, N/m.
        pub bend_k: f32,
        /// Damping of the spring to the point after next, N·s/m.
        pub bend_c: f32,
    }
}

gpu_record! {
    /// Dynamic state of one hair point (WGSL `State`): x (w = wetness) and v.
    pub struct StateGpu {
        /// Position; w is the wetness.
        pub x: [f32; 4],
        /// Velocity; w unused.
        pub v: [f32; 4],
    }
}

gpu_record! {
    /// One water particle (WGSL `Particle`): position, its water and velocity.
    pub struct ParticleGpu {
        /// Position, m.
        pub x: [f32; 3],
        /// With held water, the water it carries, quanta (0 in the paper's model, where every
        /// particle weighs `particle_mass`).
        pub mass: u32,
        /// Velocity, m/s.
        pub v: [f32; 3],
        /// With absorption: the water left after this substep's `absorb_finish`, quanta, which
        /// `water_integrate` makes the particle's `mass` once it has moved it with the water
        /// it held at the substep's start (the mass the hair's pull on it was reckoned with).
        pub left: u32,
    }
}

gpu_record! {
    /// A collider placed for one substep (WGSL `Collider`).
    pub struct ColliderGpu {
        /// Axis start (xyz) and radius (w).
        pub a: [f32; 4],
        /// Axis (xyz) and 1 / |axis|² (w).
        pub ab: [f32; 4],
        /// Velocity of the axis start over the substep, m/s (xyz; w unused).
        pub va: [f32; 4],
        /// Rate of change of the axis, 1/s (xyz; w unused): the axis point at `t` moves at
        /// `va + vab t`.
        pub vab: [f32; 4],
    }
}

/// Workgroup size of the per-point and per-particle passes.
pub const WG: u32 = 64;
/// Cells one workgroup of the grid's prefix sum covers (256 invocations x 4 cells).
pub const SCAN_BLOCK: u32 = 1024;
/// Points per workgroup of drip's count and emit (held.wgsl): a quarter as many block counts
/// for drip_scan's one workgroup to add up as workgroups of [`WG`] would leave. The emit's
/// workgroup prefix sum (scan.wgsl `scan_inclusive`) is 256 wide, so this is too.
pub const DRIP_WG: u32 = 256;
/// Workgroups per row of a 2D dispatch.
pub const MAX_GROUPS_X: u32 = 65_535;

/// Workgroup counts (x, y) that cover `n` invocations of [`WG`].
pub fn groups(n: u32) -> (u32, u32) {
    let g = n.div_ceil(WG).max(1);
    if g <= MAX_GROUPS_X {
        (g, 1)
    } else {
        (MAX_GROUPS_X, g.div_ceil(MAX_GROUPS_X))
    }
}

/// A buffer of `size` bytes (at least 16) with `usage`.
pub fn buffer(dev: &wgpu::Device, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    dev.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16).next_multiple_of(16),
        usage,
        mapped_at_creation: false,
    })
}

/// Storage usage that the host may also write and copy from.
pub const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::COPY_DST)
    .union(wgpu::BufferUsages::COPY_SRC);

/// Words per particle in the `water_force` buffer: the hair's summed reaction on it, each of x,
/// y, z as a 64-bit fixed-point integer (low word, high word), then how stiffly the hair holds
/// it as a 32-bit one ([`STIFFNESS_SCALE`]) and a word of padding, so the sums are the same in
/// any order.
pub const WATER_FORCE_WORDS: u32 = 8;

/// Where the particles gather their reactions (`reaction_gathered.wgsl`, `reactions.wgsl`):
/// the words of the `wet` buffer (its WGSL twin: `wet_layout.wgsl`), which takes `water_force`'s binding and place, and of its
/// sort order.
pub mod wet_words {
    use super::{SCAN_BLOCK, WATER_FORCE_WORDS};

    /// Words of a hair point's record: its key (its water-grid bucket + 1, 0 without a pair
    /// this substep), the place its pulls were reckoned at (3), their weight, its saturation
    /// and absorption take, and a word of padding.
    pub const RECORD: u32 = 8;

    /// The `wet` buffer: the particles' sums (as `water_force`), a count per bucket, and a
    /// record per hair point.
    pub fn words(capacity: u32, max_buckets: u32, points: u32) -> u64 {
        WATER_FORCE_WORDS as u64 * capacity as u64 + max_buckets as u64 + RECORD as u64 * points as u64
    }

    /// The `wet_order` buffer: the buckets' starts (one more than the buckets), the prefix
    /// sum's block sums, and the recorded points' indices in bucket order.
    pub fn order_words(max_buckets: u32, points: u32) -> u64 {
        max_buckets as u64 + 1 + max_buckets.div_ceil(SCAN_BLOCK) as u64 + points as u64
    }
}

/// Fixed-point units per unit of [`crate::physics::adhesion::pair_stiffness`] in a particle's
/// sum of how stiffly the hair holds it (2^16): each pair's rounding is 8e-6 of the stiffest
/// pair's, and the sum's 32 bits hold 65,535 such pairs, more than a drop finds within reach
/// of the densest groom (the paper scene's most, 430).
pub const STIFFNESS_SCALE: f32 = 65_536.0;

/// Fixed-point units per unit of adhesion strength in the adhesion sums (2^32).
pub const FIXED_SCALE: f32 = 4_294_967_296.0;

/// Words before the per-cell counts in the `grid_count` buffer (the particles' bounds as
/// order-preserving keys: lo.xyz at 0..3, hi.xyz at 3..6).
pub const GRID_COUNT_HEADER: u32 = 8;

/// The water grid's cell side on the GPU, in units of `r_max` (defined with the mark table's
/// law, which depends on it).
pub use crate::physics::hash_marks::WATER_CELL_R;

/// Word offsets of the header at the start of the `grid` buffer (the water's hashed grid,
/// `grid.wgsl`), written by `grid_setup`.
pub mod grid_header {
    /// The particles' box, lo.xyz, as f32 bits.
    pub const LO: u32 = 0;
    /// Cell side, f32 bits.
    pub const CELL: u32 = 3;
    /// 1 / cell side, f32 bits.
    pub const INV: u32 = 4;
    /// The particles' box, hi.xyz, as f32 bits.
    pub const HI: u32 = 5;
    /// Buckets in the table (a power of two).
    pub const BUCKETS: u32 = 8;
    /// Particles in the grid.
    pub const COUNT: u32 = 9;
    /// Words of this build's mark table (`physics::hash_marks`); 0: no table.
    pub const MARKS: u32 = 10;
    /// Where the mark table starts, in words (written once, at create: [`super::grid_words`]).
    pub const MARK_AT: u32 = 11;
    /// The most drops one particle of the grid stands for: coalesced drops pull as one
    /// (`piles.wgsl`'s `pile_finish` writes it each step; 0 or 1: one each).
    pub const PILE_MAX: u32 = 12;
    /// start[b] at START + b; start[buckets] = count.
    pub const START: u32 = 16;
}

/// The `grid` buffer's layout for a table of `max_buckets` buckets: where the mark table
/// starts and the words in all. The header, `start[0..=max_buckets]`, the prefix sum's
/// per-block totals (one per [`SCAN_BLOCK`] buckets), then the largest mark table, at a
/// multiple of 256 bytes so the water module can bind it apart (the smallest
/// `min_storage_buffer_offset_alignment` a device may ask is 256).
pub fn grid_words(max_buckets: u32) -> (u32, u32) {
    let block_sums = max_buckets.div_ceil(SCAN_BLOCK);
    let mark_at = (grid_header::START + max_buckets + 1 + block_sums).next_multiple_of(64);
    (
        mark_at,
        mark_at + crate::physics::hash_marks::max_mark_words(max_buckets),
    )
}

/// Word offsets and flags of the hair status block (`status`, 4 words), which every readback
/// carries first.
pub mod status {
    /// Largest v² this step (f32 bits, atomic max).
    pub const SPEED2: u32 = 0;
    /// Failure flags.
    pub const FLAGS: u32 = 1;
    /// First non-finite point (atomic min; `u32::MAX` when none).
    pub const FAILED_POINT: u32 = 2;
    /// Flag: a hair point became non-finite.
    pub const HAIR_NONFINITE: u32 = 1;
    /// Flag: a water particle became non-finite.
    pub const WATER_NONFINITE: u32 = 2;
}

/// Word offsets of the water state block (`water_state`, [`water_state::WORDS`] words; the
/// first 4 ride along with status reads).
pub mod water_state {
    /// Words in the block.
    pub const WORDS: u32 = 8;
    /// Water of the particles removed since reset, quanta (held water; 64-bit: lo, hi).
    pub const LEFT: u32 = 4;
    /// Particles held.
    pub const HELD: u32 = 0;
    /// Particles kept by the cull in progress.
    pub const KEPT: u32 = 1;
    /// Particles removed since reset.
    pub const REMOVED: u32 = 2;
    /// Drops that meet coalesce: the sources counted while a step's piles are made (0
    /// otherwise).
    pub const SOURCES: u32 = 3;
    /// Drops that meet coalesce: the drops held while their sources stand for them in the
    /// step's substeps (`HELD` is then the sources).
    pub const DROPS: u32 = 6;
    /// Drops that meet coalesce: the largest pile, while a step's piles are made.
    pub const PILE_MAX: u32 = 7;
}

/// Word offsets of one slot of the table that groups drops by pile cell (`piles.wgsl`,
/// [`pile_words::WORDS`] words a slot, [`pile_words::slots`] slots for `n` drops): drops that
/// meet coalesce on the GPU (`cpu/piles.rs` on the CPU).
pub mod pile_words {
    /// The cell's first drop to claim the slot (its key: the cell is the drop's), or
    /// [`EMPTY`].
    pub const OWNER: u32 = 0;
    /// Drops in the cell.
    pub const COUNT: u32 = 1;
    /// Nonzero when some drop of the cell differs from the owner in place or velocity.
    pub const APART: u32 = 2;
    /// The drops' offsets from the cell's corner summed, in fixed point (x, y, z as 64-bit
    /// lo, hi word pairs); after the sources are made, the source's place at the step's end
    /// (`PLACE`).
    pub const SUM_X: u32 = 3;
    /// The drops' velocities summed, in fixed point (as `SUM_X`); after the sources are made,
    /// the source's velocity at the step's end (`VEL`).
    pub const SUM_V: u32 = 9;
    /// The source's place at the step's end (f32 bits, xyz), over `SUM_X`.
    pub const PLACE: u32 = SUM_X;
    /// The source's velocity at the step's end (f32 bits, xyz), after `PLACE`.
    pub const VEL: u32 = SUM_X + 3;
    /// Words a slot.
    pub const WORDS: u32 = 15;
    /// An empty slot's `OWNER`.
    pub const EMPTY: u32 = u32::MAX;
    /// Fewest slots a table has.
    pub const MIN_SLOTS: u32 = 64;

    /// Slots of the table for `n` drops: half as many again (linear probing always finds room,
    /// and at two thirds full its runs stay short), at least [`MIN_SLOTS`]. Not rounded to a
    /// power of two (a slot is `hash % slots`): at the largest capacity, twice the drops
    /// rounded up would take a gigabyte.
    pub fn slots(n: u32) -> u32 {
        (n as u64 + n as u64 / 2).clamp(MIN_SLOTS as u64, u32::MAX as u64) as u32
    }
}

/// Word offsets of the held-water ledger block (`held_ledger`): 64-bit counts as (lo, hi)
/// word pairs, added to with integer atomics so they are exact in any order.
pub mod held_ledger {
    /// Quanta added by soaking.
    pub const ADDED: u32 = 0;
    /// Quanta evaporated.
    pub const EVAPORATED: u32 = 2;
    /// Words in the block.
    pub const WORDS: u32 = 4;
}

/// Word offsets of one point's record in the liquid bridges' buffer (`bridge`,
/// [`bridge_words::WORDS`] words per point; docs/WET_MODEL.md §5).
pub mod bridge_words {
    use crate::physics::wet::MAX_BRIDGES;
    /// Its nearest wet points of other strands at its last search, host point indices
    /// ascending.
    pub const NEAREST: u32 = 0;
    /// How many of `NEAREST` are set (0: not wet, or none found).
    pub const COUNT: u32 = MAX_BRIDGES as u32;
    /// Each bridge's coefficient, N/m (f32 bits; by `NEAREST`'s slot).
    pub const COEF: u32 = COUNT + 1;
    /// Words per point in its record.
    pub const WORDS: u32 = COEF + MAX_BRIDGES as u32;
    /// Words per point in all: its record, and after every point's record (at
    /// `Params::bridge_masks`), one word whose bit k is set when `NEAREST[k]` is a bridge this
    /// step (each among the other's nearest). The masks stand apart so that pass cohesion,
    /// every substep, reads four bytes of a point that has no bridge. After the masks, one
    /// word a point: 1 while it takes part in the bridges (as of this step's `bridge_count`),
    /// so the later parts of pass hair_grid read four bytes of a point that does not, and
    /// `bridge_count` clears a record only when its point has just left (a point that never
    /// took part has a clear record already).
    pub const PER_POINT: u32 = WORDS + 2;
}

/// Word offsets of one particle's record in the absorption scratch (`absorb`, per grid slot,
/// [`absorb_words::WORDS`] words): all zero at a substep's start (zero at creation, and
/// `absorb_finish` clears each record it has used).
pub mod absorb_words {
    /// The demands on the particle summed, quanta (64-bit: lo, hi).
    pub const TOTAL: u32 = 0;
    /// The largest demand.
    pub const BEST: u32 = 2;
    /// `!i` for the lowest point index `i` that made the largest demand (0: none), kept by
    /// an atomic max.
    pub const POINT: u32 = 3;
    /// What the particle has given this substep, quanta.
    pub const GIVEN: u32 = 4;
    /// Words per particle.
    pub const WORDS: u32 = 5;

    /// Words of the bits after the particles' records (from word `capacity * WORDS`): bit
    /// `i % 32` of word `i / 32` is set by the hair kernel when point `i` had a particle within
    /// `r_max` this substep, and cleared by `absorb`, which visits only those points (every
    /// other point asked for nothing).
    pub fn near_bits(points: u32) -> u32 {
        points.div_ceil(32)
    }

    /// The first word of a guide groom's bundles (one f32 a point, `absorb.wgsl`
    /// `bundle_at`): after the particles' records and the near bits where the scene absorbs,
    /// else the buffer's start (the bundles are then all it holds).
    pub fn bundles_at(absorbs: bool, capacity: u32, points: u32) -> u32 {
        match absorbs {
            true => capacity * WORDS + near_bits(points),
            false => 0,
        }
    }
}

/// An attribute offset meaning "not written" (`Params::pos_off` and friends).
pub const NO_ATTRIBUTE: u32 = u32::MAX;

/// Bytes at the start of each substep's uniform: the head transform (a column-major 4x4) and
/// the implicit solve's blend and step (`a, b, h, 1/h`: `physics/bdf2.rs`; `1, 0, h, 1/h` but
/// for BDF2); the placed colliders follow, one [`ColliderGpu`] each.
pub const SUBSTEP_HEAD_BYTES: u32 = 80;
