//! The C-visible structs and enums, and their conversion into the Rust API's types.

use super::boundary::Fail;
use super::enums::read_enum;
use crate::params::{MaterialParams, SimParams, SpringModel, SpringParams, VertexAttributes, WaterParams};
use crate::physics::collide::Shape;
use crate::physics::frames::transform_from_mat4;
use crate::physics::sdf::{Sdf, MAX_SDFS, MAX_SDF_CELLS};
use glam::Vec3;

/// Collider shape (`WetHairCollider::shape`).
#[repr(u32)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WetHairColliderType {
    /// Sphere: `a` is the centre, `b` is ignored.
    WETHAIR_COLLIDER_SPHERE = 0,
    /// Capsule: the points within `radius` of the segment `a`–`b`.
    WETHAIR_COLLIDER_CAPSULE = 1,
}

/// Vertex attribute bits (`WetHairSimDesc::vertex_attributes`). Present attributes are written
/// interleaved per vertex in this order: position (3 floats), tangent (3), wetness (1).
#[repr(u32)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WetHairVertexAttribute {
    /// Position, world space, metres.
    WETHAIR_ATTRIBUTE_POSITION = 1,
    /// Unit tangent along the strand (central difference; one-sided at the ends).
    WETHAIR_ATTRIBUTE_TANGENT = 2,
    /// Wetness in [0, 1].
    WETHAIR_ATTRIBUTE_WETNESS = 4,
}

/// Stiffness (N/m) and damping (N·s/m) of one spring family; 0 stiffness and damping
/// removes the family's pass.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairSpring {
    /// Stiffness k, N/m, >= 0.
    pub stiffness: f32,
    /// Damping c, N·s/m, >= 0.
    pub damping: f32,
}

/// Material properties of a strand (`WETHAIR_SPRING_MODEL_MATERIAL`): each spring's k and c
/// follow from these and its rest length, so a strand behaves the same however finely it is
/// sampled. Each >= 0 and <= 1e20.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairMaterial {
    /// Axial stiffness EA, N: a stretch spring of rest length l gets k = EA / l. Default 0.8.
    pub stretch_modulus: f32,
    /// Axial damping, N·s: c = stretch_damping / l. Default 4e-4.
    pub stretch_damping: f32,
    /// Bending stiffness EI, N·m²: a bend spring of rest span L gets k = EI / L³.
    /// Default 1.2e-6 (hair-like; the paper scene is 6.4e-4).
    pub bend_modulus: f32,
    /// Bending damping, N·m²·s: c = bend_damping / L³. Default 6e-10.
    pub bend_damping: f32,
}

impl From<MaterialParams> for WetHairMaterial {
    fn from(m: MaterialParams) -> Self {
        WetHairMaterial {
            stretch_modulus: m.stretch_modulus,
            stretch_damping: m.stretch_damping,
            bend_modulus: m.bend_modulus,
            bend_damping: m.bend_damping,
        }
    }
}

/// Water particles and their pull on hair (METHOD.md eq. 2).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairWaterDesc {
    /// Particle radius r_min, m, >= 0: hair settles on this shell.
    pub r_min: f32,
    /// Influence radius r_max, m, > r_min, in [1e-6, 10].
    pub r_max: f32,
    /// Adhesion strength s, N, >= 0: peak pull between one particle and one hair point, or
    /// between one particle and `WetHairSimDesc::water_adhesion_length` m of hair.
    pub adhesion: f32,
    /// Mass of one particle, kg, > 0.
    pub particle_mass: f32,
    /// Linear drag on particles, N·s/m, >= 0.
    pub drag: f32,
    /// Most particles held at once (<= 4,194,304); 0 means the scene never has water.
    pub capacity: u32,
    /// Wetting rate, 1/s, >= 0.
    pub wetting_rate: f32,
    /// Particles farther than this (m) from the groom's centre are removed at the end of a
    /// step; 0 = half the groom's diagonal plus its longest strand.
    pub domain_radius: f32,
}

/// A collider in head space; it follows the head transform.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairCollider {
    /// A `WetHairColliderType` value.
    pub shape: u32,
    /// Sphere centre, or capsule axis start (head space, m).
    pub a: [f32; 3],
    /// Capsule axis end (ignored for spheres).
    pub b: [f32; 3],
    /// Radius, m, > 0.
    pub radius: f32,
}

/// A signed distance field collider (since 0.4.0): `values[i + nx (j + ny k)]` is the distance,
/// m, from the point `origin + cell_size (i, j, k)` of the grid's own frame to the surface,
/// negative inside. Hair points and particles inside are pushed out along the field's gradient,
/// with the analytic colliders' friction. `transform` (column-major 4×4: rotation, translation
/// and a uniform scale) places the grid in the world at the start;
/// `wethair_sim_set_sdf_transform` moves it each frame. The values are copied at create.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairSdf {
    /// Samples along x, y and z, each >= 2; at most 16,777,216 in all.
    pub dims: [u32; 3],
    /// The first sample's position in the grid's frame, m.
    pub origin: [f32; 3],
    /// Spacing of the samples, m, > 0.
    pub cell_size: f32,
    /// Unused; keep 0.
    pub reserved: u32,
    /// `dims[0] * dims[1] * dims[2]` distances, m, x fastest, all finite.
    pub values: *const f32,
    /// Grid frame to world at the start, column-major.
    pub transform: [f32; 16],
}

/// Everything a simulation is made from. Fill with `wethair_sim_desc_init(&desc, sizeof desc)`
/// (material springs, AUTO integrator: right for any groom), or with the older
/// `wethair_sim_desc_default()` (the paper scene's exact parameters in the 0.1.0 layout), then
/// set `groom` and what differs.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairSimDesc {
    /// `sizeof(WetHairSimDesc)`, set by `wethair_sim_desc_default`.
    pub struct_size: u32,
    /// A `WetHairDampingModel` value.
    pub damping_model: u32,
    /// The strands (required; copied at create, may be destroyed after).
    pub groom: *const super::WetHairGroom,
    /// Stretch springs (i, i+1). Default 40 N/m, 0.02 N·s/m.
    pub stretch: WetHairSpring,
    /// Bend springs (i, i+2). Default 10 N/m, 0.005 N·s/m.
    pub bend: WetHairSpring,
    /// Gravity, m/s². Default (0, 0, -9.81).
    pub gravity: [f32; 3],
    /// Linear air drag on hair points, N·s/m: on each `air_drag_length` m of hair, or on
    /// every point where that is 0 (the paper's). Default 0.
    pub air_drag: f32,
    /// Substeps per step, 1..=1024. Default 4.
    pub substeps: u32,
    /// A `WetHairIntegrator` value. Default symplectic Euler (the paper's).
    pub integrator: u32,
    /// Newton iterations (implicit Euler; 1 = linearised) or constraint sweeps (XPBD) per
    /// substep, 1..=64. Default 1.
    pub solver_iterations: u32,
    /// Worker threads, 0 = one per core, at most 256.
    pub threads: u32,
    /// Water parameters.
    pub water: WetHairWaterDesc,
    /// Colliders (may be NULL when `collider_count` is 0), at most 64; copied at create.
    pub colliders: *const WetHairCollider,
    /// Number of colliders.
    pub collider_count: u32,
    /// Tangential velocity lost on collider contact, 0..=1. Default 0.2.
    pub friction: f32,
    /// OR of `WetHairVertexAttribute` bits. Default all three.
    pub vertex_attributes: u32,
    /// A `WetHairBackend` value. Default AUTO.
    pub backend: u32,
    /// A `WetHairReadback` value. Default LATEST.
    pub readback: u32,
    /// Unused; keep 0. The 0.1.0 layout ended in 4 bytes of padding here (its size, 128,
    /// counts them), so fields added since start after it, where an older host has none.
    pub reserved: u32,
    /// A `WetHairSpringModel` value (since 0.2.0): whether `stretch`/`bend` give every
    /// spring's k and c (PER_SPRING, the paper's model; what 0.1.0 hosts get) or `material`
    /// does (MATERIAL, the `wethair_sim_desc_init` default).
    pub spring_model: u32,
    /// Material properties for `WETHAIR_SPRING_MODEL_MATERIAL` (since 0.2.0).
    pub material: WetHairMaterial,
    /// Unused; keep 0. A 152-byte layout (material last) ended in 4 bytes of padding here,
    /// so the fields after it start where such a host has none.
    pub reserved2: u32,
    /// The wet model (since 0.2.0): water held by the hair and what it does. Off by default.
    pub held_water: super::wet::WetHairHeldWater,
    /// The wind at the start (since 0.2.0; `wethair_sim_set_wind` changes it). Calm by default.
    pub wind: super::wet::WetHairWind,
    /// Unused; keep 0. A 216-byte layout (0.2.0) ended here.
    pub reserved3: u32,
    /// The live error estimate (since 0.3.0; `WetHairStats::error_estimate`): 0 leaves it out
    /// (the default); N > 0 runs every N-th strand again on the CPU at twice the substeps and
    /// extrapolates the difference. Costs about 2 T / N of a step on T threads (128 on 2
    /// threads: about 3%, measured).
    pub error_estimate_stride: u32,
    /// An error budget, m (since 0.3.0; 0: off, the default): after each step the substeps
    /// double while the estimate's largest point error exceeds it and halve while half as
    /// many would keep it under half of it, between the created `substeps` (1 for the
    /// implicit integrators) and `max_substeps`; with `WETHAIR_INTEGRATOR_AUTO` it also moves
    /// between symplectic Euler and BDF2, whichever is cheaper for the tolerance. Uses the
    /// estimate (every 128th strand when `error_estimate_stride` is 0).
    /// `WetHairStats::substeps` and `integrator` say what it chose.
    pub tolerance: f32,
    /// The most substeps the budget may choose, `substeps..=512`. Default 64.
    pub max_substeps: u32,
    /// Unused; keep 0. A 232-byte layout (0.3.0) ended here.
    pub reserved4: u32,
    /// Fixed-step updates (since 0.4.0; `wethair_sim_advance`): the step, s, in (0, 1]; 0
    /// (the default) turns them off, and `wethair_sim_advance` then steps by the frame time as
    /// given. With a fixed step, hosts at any frame rate compute the same steps bit for bit.
    pub fixed_step: f32,
    /// Longest frame time one `wethair_sim_advance` simulates, s, at least `fixed_step` and
    /// at most 4096 steps (since 0.4.0): the excess of a longer frame is dropped (and
    /// reported) rather than caught up. Default 0.25.
    pub max_frame_time: f32,
    /// 1 (the default): the vertices show the state between the last two fixed steps, by the
    /// time left over; 0: the last step's state (since 0.4.0). Costs one copy of the
    /// positions per advance that steps.
    pub interpolate: u32,
    /// Unused; keep 0.
    pub reserved5: u32,
    /// SDF colliders (since 0.4.0; may be NULL when `sdf_count` is 0), at most 16; copied at
    /// create; both backends run them.
    pub sdfs: *const WetHairSdf,
    /// Number of SDF colliders.
    pub sdf_count: u32,
    /// Unused; keep 0.
    pub reserved6: u32,
    /// 1: roots on a skinned mesh (since 0.4.0): each strand's pinned points follow the frame
    /// `wethair_sim_set_root_frames` sets instead of the head transform (which still moves
    /// the colliders); with guides, followers' pinned points too. 0 (the default): roots
    /// follow the head.
    pub skinned_roots: u32,
    /// A root that moves farther than this in one step (or one `wethair_sim_advance` frame)
    /// carries its strand there rigidly, at rest, instead of sweeping it through the world, m;
    /// 0: never (since 0.4.0). Default 0.5.
    pub root_teleport_distance: f32,
    /// Hair-hair volume (since 0.4.0; off by default).
    pub volume: WetHairVolume,
    /// Guides and followers with level of detail (since 0.5.0; off by default: every strand
    /// simulated). A 296-byte layout (0.4.0) ended before it.
    pub guides: WetHairGuides,
    /// Water a kilogram of dry hair holds between its fibres against gravity, above
    /// `held_water.capacity_ratio`, kg/kg, 0..=100 (since 0.6.0; part of the wet model, here
    /// because `WetHairHeldWater` sits inside this struct and cannot grow). A point's hold
    /// limit is `capacity_ratio + held_water_free_ratio` times its dry mass: absorption
    /// fills it that far, and only the water above it runs down the strand and drips.
    /// Default 1; a 328-byte layout (0.5.0) ended before it and takes the default.
    pub held_water_free_ratio: f32,
    /// Unused; keep 0.
    pub reserved7: u32,
    /// Length of hair `held_water.flow_mobility` is quoted over, m, in (0, 1] (since 0.7.0;
    /// here for the same reason). A segment `l` long passes on `flow_mobility ·
    /// held_water_flow_length / l` of its running water a second, so water runs down a strand
    /// at `flow_mobility · held_water_flow_length` m/s (0.1 by default) however finely the
    /// strand is sampled. Default 0.02; a 336-byte layout (0.6.0) ended before it and takes the
    /// default.
    pub held_water_flow_length: f32,
    /// Unused; keep 0.
    pub reserved8: u32,
    /// The length of hair `air_drag` is quoted over, m, 0..=1 (since 0.8.0): a point takes
    /// `air_drag ℓ / air_drag_length`, `ℓ` half of each rest segment it ends, so a strand feels
    /// the same drag in a wind however finely it is sampled. 0: every point takes `air_drag`
    /// (before 0.8.0, a finer groom felt more). `wethair_sim_desc_init` gives 0.02 (the paper
    /// scene's segment); `wethair_sim_desc_default` and a 344-byte layout (0.7.0), which ended
    /// before it, give 0.
    pub air_drag_length: f32,
    /// Unused; keep 0.
    pub reserved9: u32,
    /// The length of hair `water.adhesion` is quoted over, m, 0..=1 (since 0.8.0; here because
    /// `WetHairWaterDesc` sits inside this struct and cannot grow): a point pulls with
    /// `adhesion ℓ / water_adhesion_length`, `ℓ` half of each rest segment it ends, so a drop
    /// pulls a strand alike however finely it is sampled. 0: every point pulls with
    /// `adhesion` (the paper's eq. 2; before 0.8.0 a finer groom was pulled harder).
    /// `wethair_sim_desc_init` gives 0.02 (the paper scene's segment);
    /// `wethair_sim_desc_default` and a 344-byte layout (0.7.0) give 0.
    pub water_adhesion_length: f32,
    /// Unused; keep 0.
    pub reserved10: u32,
    /// Drops that meet coalesce, m, 0..=(r_max − r_min) / 8 (since 0.9.0; `SimParams`'s
    /// `water.pile_cell`): at each step's start the drops in one cell of this side take their
    /// mean position and velocity and from then on pull as one source of eq. 2, which spares
    /// the pulls of drops piled in one well of the hair. 0 (the default, and what a 360-byte
    /// layout (0.8.0) gets): drops pass through each other, as in the paper. The paper's
    /// model only (ignored with held water); both backends.
    pub water_pile_cell: f32,
    /// Unused; keep 0.
    pub reserved11: u32,
    /// Colliders on bones of their own (since 0.10.0; may be NULL, the default, and what a
    /// 368-byte layout (0.9.0) gets: every collider follows the head). Else `collider_count`
    /// column-major 4×4 matrices, 16 floats each: collider `i`'s frame to the world at the
    /// start, a rotation, a translation and a uniform scale. Each collider's points are then
    /// in its own frame, and `wethair_sim_set_collider_transform` moves the frame each step,
    /// as a skeleton moves a shoulder or a collar under long hair. Copied at create.
    pub collider_frames: *const f32,
}

/// Which strands are guides (`WetHairGuides::choice`).
#[repr(u32)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WetHairGuideChoice {
    /// Every strand simulated, no followers (the default).
    WETHAIR_GUIDES_ALL = 0,
    /// Strands `0, count, 2 count, …` (`count` >= 1).
    WETHAIR_GUIDES_EVERY_NTH = 1,
    /// `count` strands spread evenly over the scalp, chosen by wethair.
    WETHAIR_GUIDES_SPREAD = 2,
    /// The `count` host strands listed in `strands` (each once).
    WETHAIR_GUIDES_GIVEN = 3,
    /// `count` strands chosen by wethair by clustering the roots (k-means; since 0.5.1):
    /// followers sit nearer their guides where the scalp is uneven.
    WETHAIR_GUIDES_CLUSTER = 4,
}

/// Guides and followers (since 0.5.0; docs/GUIDES.md): the backend simulates the guides only,
/// and writes every strand's vertices, each follower from its nearest guides (roots), wet
/// followers closing on their nearest guide. `wethair_sim_set_guide_fraction` changes the
/// simulated fraction at run time without pops.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairGuides {
    /// A `WetHairGuideChoice`. Default `WETHAIR_GUIDES_ALL`.
    pub choice: u32,
    /// `n` of every n-th, the spread or cluster choice's guide count, or the length of
    /// `strands`.
    pub count: u32,
    /// The given guides' host strand indices (`WETHAIR_GUIDES_GIVEN` only; may be NULL
    /// otherwise); copied at create.
    pub strands: *const u32,
    /// Guides per follower: 1 or 3. Default 3.
    pub per_follower: u32,
    /// How far a wet follower closes on its nearest guide, 0..=1 (its offset shrinks by
    /// `clump × wetness`). Default 0.8.
    pub clump: f32,
    /// The fraction of the guides simulated at create, (0, 1]. Default 1.
    pub fraction: f32,
    /// Seconds over which a change of the fraction blends the output, >= 0. Default 0.25.
    pub blend_time: f32,
}

impl From<&crate::Guides> for WetHairGuides {
    fn from(g: &crate::Guides) -> Self {
        use crate::GuideChoice as C;
        let (choice, count) = match &g.choice {
            C::All => (WetHairGuideChoice::WETHAIR_GUIDES_ALL, 0),
            C::EveryNth(n) => (WetHairGuideChoice::WETHAIR_GUIDES_EVERY_NTH, *n),
            C::Spread(c) => (WetHairGuideChoice::WETHAIR_GUIDES_SPREAD, *c),
            C::Cluster(c) => (WetHairGuideChoice::WETHAIR_GUIDES_CLUSTER, *c),
            // A given list has no pointer to hand back; the defaults never hold one.
            C::Given(l) => (WetHairGuideChoice::WETHAIR_GUIDES_GIVEN, l.len() as u32),
        };
        WetHairGuides {
            choice: choice as u32,
            count,
            strands: std::ptr::null(),
            per_follower: g.per_follower,
            clump: g.clump,
            fraction: g.fraction,
            blend_time: g.blend_time,
        }
    }
}

impl WetHairGuides {
    /// As [`crate::Guides`], the given list copied (its floats and indices are checked by
    /// `SimParams::validate` and at create).
    ///
    /// # Safety
    /// `strands` holds `count` indices when the choice is `WETHAIR_GUIDES_GIVEN`.
    unsafe fn params(&self) -> Result<crate::Guides, Fail> {
        use crate::GuideChoice as C;
        let choice = match super::enums::read_enum::<WetHairGuideChoice>(self.choice, "guides.choice")? {
            WetHairGuideChoice::WETHAIR_GUIDES_ALL => C::All,
            WetHairGuideChoice::WETHAIR_GUIDES_EVERY_NTH => C::EveryNth(self.count),
            WetHairGuideChoice::WETHAIR_GUIDES_SPREAD => C::Spread(self.count),
            WetHairGuideChoice::WETHAIR_GUIDES_CLUSTER => C::Cluster(self.count),
            WetHairGuideChoice::WETHAIR_GUIDES_GIVEN => {
                if self.count as usize > crate::groom::MAX_STRANDS {
                    return Err(Fail(
                        super::WetHairResult::WETHAIR_ERROR_CAPACITY,
                        format!(
                            "guides.count {} exceeds {} strands",
                            self.count,
                            crate::groom::MAX_STRANDS
                        ),
                    ));
                }
                if self.count > 0 && self.strands.is_null() {
                    return Err(super::boundary::null("guides.strands"));
                }
                let list = if self.count == 0 {
                    Vec::new()
                } else {
                    std::slice::from_raw_parts(self.strands, self.count as usize).to_vec()
                };
                C::Given(list)
            }
        };
        Ok(crate::Guides {
            choice,
            per_follower: self.per_follower,
            clump: self.clump,
            fraction: self.fraction,
            blend_time: self.blend_time,
        })
    }
}

/// Hair-hair volume (since 0.4.0; docs/VOLUME.md): once a step the hair's mass and momentum
/// are spread over a grid that follows the head; where the hair packs denser than at rest a
/// pressure pushes it apart (the groom keeps its volume), and each point's velocity relaxes
/// toward the hair's around it (hair-hair friction). Both backends run it.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairVolume {
    /// 1: on; 0 (the default): off (no grid, no pass).
    pub enabled: u32,
    /// The grid's cell, m, in (0, 1]. Default 0.02.
    pub cell: f32,
    /// Pressure stiffness, m²/s², >= 0: a point where the density exceeds the rest density
    /// accelerates by `pressure · ∇ρ / ρ_rest`. Default 1 (stable while `√pressure · dt` is
    /// under a cell: below 1.44 at 60 Hz with 2 cm cells).
    pub pressure: f32,
    /// Hair-hair friction, 1/s, >= 0: each step a point's velocity moves
    /// `1 - exp(-friction dt)` of the way to the hair's around it. Default 4.
    pub friction: f32,
    /// The density above which the pressure acts, kg/m³; 0 (the default) measures it from the
    /// rest pose (the density 90% of the free hair's mass sees at rest or less).
    pub rest_density: f32,
    /// Unused; keep 0.
    pub reserved: u32,
}

impl From<crate::Volume> for WetHairVolume {
    fn from(v: crate::Volume) -> Self {
        WetHairVolume {
            enabled: v.enabled as u32,
            cell: v.cell,
            pressure: v.pressure,
            friction: v.friction,
            rest_density: v.rest_density,
            reserved: 0,
        }
    }
}

impl WetHairVolume {
    /// As [`crate::Volume`] (its floats are checked by `SimParams::validate`).
    fn params(&self) -> Result<crate::Volume, Fail> {
        let enabled = match self.enabled {
            0 => false,
            1 => true,
            v => {
                return Err(Fail(
                    super::WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT,
                    format!("volume.enabled must be 0 or 1, got {v}"),
                ))
            }
        };
        Ok(crate::Volume {
            enabled,
            cell: self.cell,
            pressure: self.pressure,
            friction: self.friction,
            rest_density: self.rest_density,
        })
    }
}

/// What one `wethair_sim_advance` did (since 0.4.0). The host sets `struct_size` first.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct WetHairAdvance {
    /// `sizeof(WetHairAdvance)`, set by the host.
    pub struct_size: u32,
    /// Fixed steps taken (0 when the frame was shorter than what the next step needed).
    pub steps: u32,
    /// Where the vertices lie between the state before the last step (0) and after it (1);
    /// 1 without fixed steps or interpolation.
    pub blend: f32,
    /// Frame time dropped by `max_frame_time`, s.
    pub dropped_time: f32,
}

/// The host's own strands. Fill with `wethair_groom_desc_default()`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairGroomDesc {
    /// `sizeof(WetHairGroomDesc)`.
    pub struct_size: u32,
    /// Number of strands, >= 1.
    pub strand_count: u32,
    /// Points per strand (`strand_count` entries, each 2..=256).
    pub strand_point_counts: *const u32,
    /// Rest positions, x y z per point, strand after strand, head space (m).
    pub positions: *const f32,
    /// Number of points (the sum of `strand_point_counts`).
    pub point_count: u32,
    /// Per point, non-zero = pinned to the head. NULL pins each strand's first point.
    pub pinned: *const u8,
    /// Per point mass, kg. NULL gives every point `default_mass`.
    pub masses: *const f32,
    /// Mass of every point when `masses` is NULL, kg, > 0. Default 1e-3.
    pub default_mass: f32,
}

impl WetHairGroomDesc {
    /// Empty arrays, 1 g per point, and this struct's size.
    pub fn default_values() -> Self {
        WetHairGroomDesc {
            struct_size: std::mem::size_of::<WetHairGroomDesc>() as u32,
            strand_count: 0,
            strand_point_counts: std::ptr::null(),
            positions: std::ptr::null(),
            point_count: 0,
            pinned: std::ptr::null(),
            masses: std::ptr::null(),
            default_mass: 1.0e-3,
        }
    }
}

/// How `wethair_groom_load_with_desc` reads a groom file into simulation units. Fill with
/// `wethair_load_desc_default()` (the file's units and axes, 1 g per metre, segments under 0.1 mm
/// welded), then set what differs.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairLoadDesc {
    /// `sizeof(WetHairLoadDesc)`, set by `wethair_load_desc_default`.
    pub struct_size: u32,
    /// Metres per file unit, > 0 (0.01 for centimetres). Default 1.
    pub scale: f32,
    /// A `WetHairUpAxis` value: `WETHAIR_UP_AXIS_Y_TO_Z` turns a y-up file to the simulation's
    /// z up. Default `WETHAIR_UP_AXIS_KEEP`.
    pub up_axis: u32,
    /// Mass of every point, kg, > 0, used when `linear_density` is 0. Default 1e-3.
    pub point_mass: f32,
    /// Mass per metre of strand, kg/m, >= 0; > 0 gives each point half of its two segments'
    /// mass, so the mass does not depend on how finely the file samples its strands.
    /// Default 1e-3 (a wisp of about 150 hairs).
    pub linear_density: f32,
    /// Keep every Nth strand, >= 1. Default 1 (all).
    pub strand_stride: u32,
    /// Resample each strand to this many points evenly spaced along its length: 0 (keep the
    /// file's points) or 2..=256. Default 0.
    pub resample_points: u32,
    /// Segments shorter than this (m, after `scale`) are welded and strands shorter than it
    /// dropped; `wethair_groom_get_load_message` says how many. 0 keeps every point.
    /// Default 1e-4 (0.1 mm).
    pub weld_length: f32,
}

impl WetHairLoadDesc {
    /// The defaults `wethair_load_desc_default` writes.
    pub fn default_values() -> Self {
        let o = crate::groom::LoadOptions::default();
        WetHairLoadDesc {
            struct_size: std::mem::size_of::<Self>() as u32,
            scale: o.scale,
            up_axis: o.up_axis as u32,
            point_mass: o.point_mass,
            linear_density: o.linear_density,
            strand_stride: o.strand_stride,
            resample_points: o.resample_points,
            weld_length: o.weld_length,
        }
    }

    /// The options, or the first invalid field.
    pub(crate) fn options(&self) -> Result<crate::groom::LoadOptions, Fail> {
        let o = crate::groom::LoadOptions {
            scale: self.scale,
            up_axis: read_enum(self.up_axis, "up_axis")?,
            point_mass: self.point_mass,
            linear_density: self.linear_density,
            strand_stride: self.strand_stride,
            resample_points: self.resample_points,
            weld_length: self.weld_length,
        };
        o.validate()?;
        Ok(o)
    }
}

/// Where each attribute sits in the interleaved vertex buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct WetHairVertexLayout {
    /// `sizeof(WetHairVertexLayout)`, set by the host before the call.
    pub struct_size: u32,
    /// Vertices written (all points of all strands, strand after strand).
    pub vertex_count: u32,
    /// Strands.
    pub strand_count: u32,
    /// Floats per vertex.
    pub stride_floats: u32,
    /// Byte offset of the position (3 × f32), or -1 when not requested.
    pub position_offset: i32,
    /// Byte offset of the tangent (3 × f32), or -1.
    pub tangent_offset: i32,
    /// Byte offset of the wetness (1 × f32), or -1.
    pub wetness_offset: i32,
}

/// Counters and measures of a simulation.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct WetHairStats {
    /// `sizeof(WetHairStats)`, set by the host before the call.
    pub struct_size: u32,
    /// Strands.
    pub strands: u32,
    /// Hair points.
    pub points: u32,
    /// Water particles now.
    pub particles: u32,
    /// Particles removed for leaving the domain since create or reset.
    pub particles_removed: u64,
    /// Steps since create or reset.
    pub steps: u64,
    /// Wall time of the last step, ms.
    pub last_step_ms: f32,
    /// Largest point speed in the last step, m/s.
    pub max_speed: f32,
    /// Mean distance from each strand tip to the nearest other tip, m (computed on request by
    /// `wethair_sim_get_stats`; -1 from `wethair_sim_get_counters`).
    pub clumping: f32,
    /// Worker threads.
    pub threads: u32,
    /// The `WetHairIntegrator` in use (AUTO resolved).
    pub integrator: u32,
    /// The `WetHairBackend` in use (AUTO resolved: CPU or GPU).
    pub backend: u32,
    /// Since 0.2.0: the clumping measure along the strands, m: the mean distance from a point
    /// to the nearest other strand's point at the same place along its strand, averaged over
    /// the quarter points (tips included). Long hair bundles along its length even where the
    /// tips still fan out; this sees it. Computed on request (-1 from
    /// `wethair_sim_get_counters`).
    pub clumping_along: f32,
    /// Since 0.2.0, with held water (else 0): where the water went, in whole
    /// `WETHAIR_WATER_QUANTUM_KG` units, exactly: `water_added` equals `water_in_particles +
    /// water_held + water_left + water_evaporated`. Added since create or reset (particles
    /// the host added, soaking).
    pub water_added: u64,
    /// In free particles now (drops the hair shed included).
    pub water_in_particles: u64,
    /// Held by the hair now.
    pub water_held: u64,
    /// Left the simulation: particles that fell out of the domain or were cleared.
    pub water_left: u64,
    /// Evaporated from the hair.
    pub water_evaporated: u64,
    /// Since 0.3.0, with `WetHairSimDesc::error_estimate_stride` set (else -1): how far the
    /// hair's positions are from the exact solution of the model, m, root mean square over the
    /// sampled strands' points, by Richardson extrapolation against a run at twice the
    /// substeps. -1 also while water couples strands (particles, liquid bridges), where one
    /// strand run alone cannot stand for the groom. Computed on request.
    pub error_estimate: f32,
    /// The largest error over the sampled strands' points, m (-1 as `error_estimate`).
    pub error_estimate_max: f32,
    /// Since 0.3.0: the substeps the last step ran (the error budget's choice, else the
    /// desc's).
    pub substeps: u32,
    /// Unused (the layout's end).
    pub reserved: u32,
}

/// Which backend runs a simulation, on what, and why AUTO chose it.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WetHairBackendInfo {
    /// `sizeof(WetHairBackendInfo)`, set by the host before the call.
    pub struct_size: u32,
    /// The `WetHairBackend` in use (CPU or GPU).
    pub backend: u32,
    /// The adapter's name and API, or the CPU's thread count; NUL-terminated, cut to fit.
    pub device: [std::ffi::c_char; 128],
    /// Why AUTO chose the CPU; empty when it did not fall back. NUL-terminated, cut to fit.
    pub fallback_reason: [std::ffi::c_char; 256],
}

impl WetHairSimDesc {
    /// The defaults of the 0.1.0 layout (what `wethair_sim_desc_default` writes and what the
    /// fields past an older host's size take): the paper scene's parameters with per-spring
    /// constants, no groom, no collider.
    pub fn default_values() -> Self {
        Self::from_params(&SimParams::paper())
    }

    /// The defaults of the current layout (`wethair_sim_desc_init` with the full size):
    /// [`SimParams::default`], no groom, no collider.
    pub fn current_values() -> Self {
        Self::from_params(&SimParams::default())
    }

    /// `p` as a desc (no groom; colliders are not carried).
    fn from_params(p: &SimParams) -> Self {
        let w = p.water;
        WetHairSimDesc {
            struct_size: std::mem::size_of::<Self>() as u32,
            damping_model: p.damping_model as u32,
            groom: std::ptr::null(),
            stretch: WetHairSpring {
                stiffness: p.stretch.stiffness,
                damping: p.stretch.damping,
            },
            bend: WetHairSpring {
                stiffness: p.bend.stiffness,
                damping: p.bend.damping,
            },
            gravity: p.gravity.to_array(),
            air_drag: p.air_drag,
            substeps: p.substeps,
            integrator: p.integrator as u32,
            solver_iterations: p.solver_iterations,
            threads: p.threads,
            water: WetHairWaterDesc {
                r_min: w.r_min,
                r_max: w.r_max,
                adhesion: w.adhesion,
                particle_mass: w.particle_mass,
                drag: w.drag,
                capacity: w.capacity,
                wetting_rate: w.wetting_rate,
                domain_radius: w.domain_radius,
            },
            colliders: std::ptr::null(),
            collider_count: 0,
            friction: p.friction,
            vertex_attributes: p.attributes.0,
            backend: p.backend as u32,
            readback: p.readback as u32,
            reserved: 0,
            spring_model: p.spring_model as u32,
            material: p.material.into(),
            reserved2: 0,
            held_water: p.held_water.into(),
            wind: p.wind.into(),
            reserved3: 0,
            error_estimate_stride: p.error_estimate_stride,
            tolerance: p.tolerance,
            max_substeps: p.max_substeps,
            reserved4: 0,
            fixed_step: p.fixed_step.step,
            max_frame_time: p.fixed_step.max_frame,
            interpolate: p.fixed_step.interpolate as u32,
            reserved5: 0,
            sdfs: std::ptr::null(),
            sdf_count: 0,
            reserved6: 0,
            skinned_roots: p.skinned_roots as u32,
            root_teleport_distance: p.root_teleport_distance,
            volume: p.volume.into(),
            guides: (&p.guides).into(),
            held_water_free_ratio: p.held_water.free_ratio,
            reserved7: 0,
            held_water_flow_length: p.held_water.flow_length,
            reserved8: 0,
            air_drag_length: p.air_drag_length,
            reserved9: 0,
            water_adhesion_length: w.adhesion_length,
            reserved10: 0,
            water_pile_cell: w.pile_cell,
            reserved11: 0,
            collider_frames: std::ptr::null(),
        }
    }

    /// The `n` colliders' own frames (none where `collider_frames` is NULL), each checked as
    /// a frame ([`crate::physics::frames::transform_from_mat4`]).
    fn collider_frame_params(&self, n: usize) -> Result<Vec<glam::Affine3A>, Fail> {
        if self.collider_frames.is_null() || n == 0 {
            return Ok(Vec::new());
        }
        let first = self.collider_frames as *const [f32; 16];
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            // SAFETY: the host's array holds `collider_count` matrices of 16 floats (the
            // documented contract); read unaligned, as every matrix the host passes.
            let m = unsafe { std::ptr::read_unaligned(first.add(i)) };
            out.push(transform_from_mat4(
                glam::Mat4::from_cols_array(&m),
                &format!("collider {i}'s frame"),
            )?);
        }
        Ok(out)
    }

    /// The SDF colliders, their arrays copied (counts and pointers checked here, values by
    /// [`SimParams::validate`]).
    fn sdf_params(&self) -> Result<Vec<std::sync::Arc<Sdf>>, Fail> {
        use super::WetHairResult::WETHAIR_ERROR_CAPACITY;
        let n = self.sdf_count as usize;
        if n > MAX_SDFS {
            return Err(Fail(
                WETHAIR_ERROR_CAPACITY,
                format!("sdf_count {n} exceeds {MAX_SDFS}"),
            ));
        }
        if n == 0 {
            return Ok(Vec::new());
        }
        if self.sdfs.is_null() {
            return Err(super::boundary::null("sdfs"));
        }
        // SAFETY: the host's array holds `sdf_count` entries (the documented contract).
        let raw = unsafe { std::slice::from_raw_parts(self.sdfs, n) };
        let mut out = Vec::with_capacity(n);
        for (i, d) in raw.iter().enumerate() {
            let cells: u64 = d.dims.iter().map(|&c| c as u64).product();
            if cells > MAX_SDF_CELLS {
                return Err(Fail(
                    WETHAIR_ERROR_CAPACITY,
                    format!("SDF {i}: {cells} samples exceed {MAX_SDF_CELLS}"),
                ));
            }
            if d.values.is_null() && cells > 0 {
                return Err(super::boundary::null("sdfs[].values"));
            }
            let values = if cells == 0 {
                Vec::new()
            } else {
                // SAFETY: the host's array holds the product of `dims` floats.
                unsafe { std::slice::from_raw_parts(d.values, cells as usize) }.to_vec()
            };
            let name = format!("SDF {i}");
            let transform = transform_from_mat4(glam::Mat4::from_cols_array(&d.transform), &name)?;
            out.push(std::sync::Arc::new(Sdf {
                dims: d.dims,
                origin: Vec3::from(d.origin),
                cell: d.cell_size,
                values,
                transform,
            }));
        }
        Ok(out)
    }

    /// Converts to [`SimParams`], checking the enums and the collider array (floats are
    /// checked by [`SimParams::validate`]).
    pub(crate) fn params(&self) -> Result<SimParams, Fail> {
        let damping_model = read_enum(self.damping_model, "damping_model")?;
        let integrator = read_enum(self.integrator, "integrator")?;
        let backend = read_enum(self.backend, "backend")?;
        let readback = read_enum(self.readback, "readback")?;
        let spring_model: SpringModel = read_enum(self.spring_model, "spring_model")?;
        let n = self.collider_count as usize;
        if n > crate::params::MAX_COLLIDERS {
            return Err(Fail(
                super::WetHairResult::WETHAIR_ERROR_CAPACITY,
                format!("collider_count {n} exceeds {}", crate::params::MAX_COLLIDERS),
            ));
        }
        let raw: &[WetHairCollider] = if n == 0 {
            &[]
        } else if self.colliders.is_null() {
            return Err(super::boundary::null("colliders"));
        } else {
            unsafe { std::slice::from_raw_parts(self.colliders, n) }
        };
        let mut colliders = Vec::with_capacity(n);
        for (i, c) in raw.iter().enumerate() {
            colliders.push(match read_enum(c.shape, &format!("collider {i}'s shape"))? {
                WetHairColliderType::WETHAIR_COLLIDER_SPHERE => Shape::Sphere {
                    center: Vec3::from(c.a),
                    radius: c.radius,
                },
                WetHairColliderType::WETHAIR_COLLIDER_CAPSULE => Shape::Capsule {
                    a: Vec3::from(c.a),
                    b: Vec3::from(c.b),
                    radius: c.radius,
                },
            });
        }
        let collider_frames = self.collider_frame_params(n)?;
        let sdfs = self.sdf_params()?;
        let w = &self.water;
        Ok(SimParams {
            stretch: SpringParams {
                stiffness: self.stretch.stiffness,
                damping: self.stretch.damping,
            },
            bend: SpringParams {
                stiffness: self.bend.stiffness,
                damping: self.bend.damping,
            },
            spring_model,
            material: MaterialParams {
                stretch_modulus: self.material.stretch_modulus,
                stretch_damping: self.material.stretch_damping,
                bend_modulus: self.material.bend_modulus,
                bend_damping: self.material.bend_damping,
            },
            damping_model,
            gravity: Vec3::from(self.gravity),
            air_drag: self.air_drag,
            air_drag_length: self.air_drag_length,
            substeps: self.substeps,
            integrator,
            solver_iterations: self.solver_iterations,
            threads: self.threads,
            water: WaterParams {
                r_min: w.r_min,
                r_max: w.r_max,
                adhesion: w.adhesion,
                adhesion_length: self.water_adhesion_length,
                particle_mass: w.particle_mass,
                drag: w.drag,
                capacity: w.capacity,
                wetting_rate: w.wetting_rate,
                domain_radius: w.domain_radius,
                pile_cell: self.water_pile_cell,
            },
            colliders,
            collider_frames,
            sdfs,
            friction: self.friction,
            attributes: VertexAttributes(self.vertex_attributes),
            backend,
            readback,
            held_water: crate::HeldWater {
                free_ratio: self.held_water_free_ratio,
                flow_length: self.held_water_flow_length,
                ..self.held_water.params()?
            },
            volume: self.volume.params()?,
            guides: unsafe { self.guides.params()? },
            wind: self.wind.into(),
            error_estimate_stride: self.error_estimate_stride,
            tolerance: self.tolerance,
            max_substeps: self.max_substeps,
            skinned_roots: match self.skinned_roots {
                0 => false,
                1 => true,
                v => {
                    return Err(Fail(
                        super::WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT,
                        format!("skinned_roots must be 0 or 1, got {v}"),
                    ))
                }
            },
            root_teleport_distance: self.root_teleport_distance,
            fixed_step: crate::FixedStep {
                step: self.fixed_step,
                max_frame: self.max_frame_time,
                interpolate: match self.interpolate {
                    0 => false,
                    1 => true,
                    v => {
                        return Err(Fail(
                            super::WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT,
                            format!("interpolate must be 0 or 1, got {v}"),
                        ))
                    }
                },
            },
        })
    }
}
