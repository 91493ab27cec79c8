//! The WGSL prelude generated from the Rust definitions: every struct the shaders share with
//! the host and every constant both sides use is written here once, in Rust, and printed into
//! the top of each module ([`prelude`]). `tests/shaders.rs` reads the compiled modules back
//! through naga and checks each struct's member offsets and size against the Rust record.

use super::buffers::{
    self, grid_header as gh, BlendGpu, CarryGpu, ColliderGpu, FollowStrandGpu, FollowUniformGpu, Params, ParticleGpu,
    PinGpu, PointGpu, RootPairGpu, RootsUniformGpu, SdfGpu, StateGpu, VolumeStepGpu,
};

/// A field type with a WGSL spelling.
pub trait WgslType {
    /// The type as WGSL writes it.
    const WGSL: &'static str;
}

impl WgslType for f32 {
    const WGSL: &'static str = "f32";
}
impl WgslType for u32 {
    const WGSL: &'static str = "u32";
}
impl WgslType for [f32; 3] {
    const WGSL: &'static str = "vec3<f32>";
}
impl WgslType for [f32; 4] {
    const WGSL: &'static str = "vec4<f32>";
}
impl WgslType for [u32; 4] {
    const WGSL: &'static str = "vec4<u32>";
}

/// One field of a [`GpuRecord`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    /// The field's name, the same in Rust and WGSL.
    pub name: &'static str,
    /// Its WGSL type.
    pub wgsl: &'static str,
    /// Its byte offset in the Rust record.
    pub offset: usize,
}

/// A `#[repr(C)]` record the shaders read with the same layout: its fields in order.
pub trait GpuRecord: bytemuck::Pod {
    /// Fields in declaration order.
    const FIELDS: &'static [Field];
}

/// Declares a GPU record: the `#[repr(C)]` Pod struct and its [`GpuRecord`] field table, from
/// one list of fields.
macro_rules! gpu_record {
    ($(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $field:ident: $ty:ty,)* }) => {
        $(#[$m])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name {
            $($(#[$fm])* pub $field: $ty,)*
        }

        impl $crate::gpu::wgsl::GpuRecord for $name {
            const FIELDS: &'static [$crate::gpu::wgsl::Field] = &[$($crate::gpu::wgsl::Field {
                name: stringify!($field),
                wgsl: <$ty as $crate::gpu::wgsl::WgslType>::WGSL,
                offset: std::mem::offset_of!($name, $field),
            },)*];
        }
    };
}
pub(crate) use gpu_record;

/// The WGSL structs the host writes or reads, by WGSL name, with their Rust records'
/// fields and sizes.
pub fn records() -> [(&'static str, &'static [Field], usize); 14] {
    fn rec<T: GpuRecord>(name: &'static str) -> (&'static str, &'static [Field], usize) {
        (name, T::FIELDS, std::mem::size_of::<T>())
    }
    [
        rec::<Params>("Params"),
        rec::<PointGpu>("Point"),
        rec::<StateGpu>("State"),
        rec::<ParticleGpu>("Particle"),
        rec::<ColliderGpu>("Collider"),
        rec::<BlendGpu>("Blend"),
        rec::<SdfGpu>("Sdf"),
        rec::<RootPairGpu>("RootPair"),
        rec::<PinGpu>("Pin"),
        rec::<CarryGpu>("Carry"),
        rec::<RootsUniformGpu>("RootsUniform"),
        rec::<VolumeStepGpu>("VolumeStep"),
        rec::<FollowUniformGpu>("FollowUniform"),
        rec::<FollowStrandGpu>("FollowStrand"),
    ]
}

/// A constant of the prelude: a `u32` or an `f32`.
#[derive(Clone, Copy, Debug)]
pub enum Const {
    /// Written `Nu`.
    U32(u32),
    /// Written in the shortest form that reads back to the same f32.
    F32(f32),
}

/// Every constant the shaders share with Rust, by WGSL name (scene constants such as `AXIAL`
/// come from [`crate::gpu::pipelines::SceneConsts`] instead).
pub fn constants() -> Vec<(&'static str, Const)> {
    use crate::physics::{adhesion, collide, implicit, spring};
    use Const::*;
    vec![
        ("WG", U32(buffers::WG)),
        ("MAX_GROUPS_X", U32(buffers::MAX_GROUPS_X)),
        ("SCAN_BLOCK", U32(buffers::SCAN_BLOCK)),
        ("DRIP_WG", U32(buffers::DRIP_WG)),
        ("GRID_COUNT_HEADER", U32(buffers::GRID_COUNT_HEADER)),
        ("WATER_FORCE_WORDS", U32(buffers::WATER_FORCE_WORDS)),
        ("WET_RECORD", U32(buffers::wet_words::RECORD)),
        ("FIXED_SCALE", F32(buffers::FIXED_SCALE)),
        ("STIFFNESS_SCALE", F32(buffers::STIFFNESS_SCALE)),
        ("G_LO", U32(gh::LO)),
        ("G_CELL", U32(gh::CELL)),
        ("G_INV", U32(gh::INV)),
        ("G_HI", U32(gh::HI)),
        ("G_BUCKETS", U32(gh::BUCKETS)),
        ("MIN_BUCKETS", U32(crate::physics::hash_grid::MIN_BUCKETS as u32)),
        ("WATER_CELL_R", F32(buffers::WATER_CELL_R)),
        ("G_COUNT", U32(gh::COUNT)),
        ("G_START", U32(gh::START)),
        ("G_MARKS", U32(gh::MARKS)),
        ("G_MARK_AT", U32(gh::MARK_AT)),
        ("MARK_MARGIN", F32(crate::physics::hash_marks::MARK_MARGIN)),
        (
            "MARK_WORDS_PER_BUCKET",
            U32(crate::physics::hash_marks::MARK_WORDS_PER_BUCKET),
        ),
        ("MAX_MARK_WORDS", U32(crate::physics::hash_marks::MAX_MARK_WORDS)),
        ("STATUS_SPEED2", U32(buffers::status::SPEED2)),
        ("STATUS_FLAGS", U32(buffers::status::FLAGS)),
        ("STATUS_FAILED_POINT", U32(buffers::status::FAILED_POINT)),
        ("FLAG_HAIR_NONFINITE", U32(buffers::status::HAIR_NONFINITE)),
        ("FLAG_WATER_NONFINITE", U32(buffers::status::WATER_NONFINITE)),
        ("WATER_HELD", U32(buffers::water_state::HELD)),
        ("WATER_KEPT", U32(buffers::water_state::KEPT)),
        ("WATER_REMOVED", U32(buffers::water_state::REMOVED)),
        ("WATER_LEFT", U32(buffers::water_state::LEFT)),
        ("WATER_STATE_WORDS", U32(buffers::water_state::WORDS)),
        ("WATER_SOURCES", U32(buffers::water_state::SOURCES)),
        ("WATER_DROPS", U32(buffers::water_state::DROPS)),
        ("WATER_PILE_MAX", U32(buffers::water_state::PILE_MAX)),
        ("G_PILE_MAX", U32(gh::PILE_MAX)),
        ("PILE_OWNER", U32(buffers::pile_words::OWNER)),
        ("PILE_COUNT", U32(buffers::pile_words::COUNT)),
        ("PILE_APART", U32(buffers::pile_words::APART)),
        ("PILE_SUM_X", U32(buffers::pile_words::SUM_X)),
        ("PILE_SUM_V", U32(buffers::pile_words::SUM_V)),
        ("PILE_PLACE", U32(buffers::pile_words::PLACE)),
        ("PILE_VEL", U32(buffers::pile_words::VEL)),
        ("PILE_WORDS", U32(buffers::pile_words::WORDS)),
        ("PILE_EMPTY", U32(buffers::pile_words::EMPTY)),
        ("PILE_MIN_SLOTS", U32(buffers::pile_words::MIN_SLOTS)),
        ("PILE_VELOCITY_UNIT", F32(crate::cpu::piles::VELOCITY_UNIT)),
        ("NO_ATTRIBUTE", U32(buffers::NO_ATTRIBUTE)),
        ("HELD_ADDED", U32(buffers::held_ledger::ADDED)),
        ("HELD_EVAPORATED", U32(buffers::held_ledger::EVAPORATED)),
        ("HELD_LEDGER_WORDS", U32(buffers::held_ledger::WORDS)),
        ("ABS_TOTAL", U32(buffers::absorb_words::TOTAL)),
        ("ABS_BEST", U32(buffers::absorb_words::BEST)),
        ("ABS_POINT", U32(buffers::absorb_words::POINT)),
        ("ABS_GIVEN", U32(buffers::absorb_words::GIVEN)),
        ("HELD_LIMIT", U32(crate::physics::wet::HELD_LIMIT)),
        ("ABSORB_SHARE_SCALE", F32(crate::physics::wet::ABSORB_SHARE_SCALE)),
        ("ABS_WORDS", U32(buffers::absorb_words::WORDS)),
        ("MAX_BRIDGES", U32(crate::physics::wet::MAX_BRIDGES as u32)),
        ("BRIDGE_SEARCH_TURNS", U32(crate::physics::wet::BRIDGE_SEARCH_TURNS)),
        ("BRIDGE_MIN_PARTS", U32(crate::physics::wet::BRIDGE_MIN_PARTS)),
        ("BR_NEAREST", U32(buffers::bridge_words::NEAREST)),
        ("BR_COUNT", U32(buffers::bridge_words::COUNT)),
        ("BR_COEF", U32(buffers::bridge_words::COEF)),
        ("BR_WORDS", U32(buffers::bridge_words::WORDS)),
        ("WATER_QUANTUM", F32(crate::physics::wet::WATER_QUANTUM as f32)),
        ("BAND", U32(implicit::BAND as u32)),
        ("MIN_LENGTH", F32(spring::MIN_LENGTH)),
        ("MIN_DISTANCE", F32(adhesion::MIN_DISTANCE)),
        (
            "PULL_STIFFNESS_LIMIT",
            F32(crate::physics::pull_limit::PULL_STIFFNESS_LIMIT),
        ),
        ("ON_AXIS_D2", F32(collide::ON_AXIS_D2)),
        ("PIVOT_FLOOR_F32", F32(implicit::PIVOT_FLOOR_F32)),
        ("ARMIJO_C1", F32(implicit::ARMIJO_C1 as f32)),
        ("ARMIJO_SLACK_F32", F32(implicit::ARMIJO_SLACK_F32)),
        ("SUBSTEP_HEAD_BYTES", U32(buffers::SUBSTEP_HEAD_BYTES)),
        ("TURN_EPS", F32(crate::physics::follow::TURN_EPS)),
        ("MAX_SPREAD_SPEED", F32(crate::physics::volume::MAX_SPREAD_SPEED)),
        (
            "VOLUME_QUANTA",
            F32((1.0 / crate::physics::volume::MASS_QUANTUM) as f32),
        ),
    ]
}

/// The generated part of every module's prelude: constants, then the shared structs (the
/// per-substep uniform last, as it holds `NC` colliders, a scene constant).
pub fn prelude() -> String {
    let mut s = String::from("// Generated from the Rust definitions (gpu/wgsl.rs): constants and shared structs.\n");
    for (name, c) in constants() {
        s.push_str(&match c {
            Const::U32(v) => format!("const {name}: u32 = {v}u;\n"),
            Const::F32(v) => format!("const {name}: f32 = {v:e};\n"),
        });
    }
    for (name, fields, _) in records() {
        s.push_str(&format!("struct {name} {{\n"));
        for f in fields {
            s.push_str(&format!("    {}: {},\n", f.name, f.wgsl));
        }
        s.push_str("}\n");
    }
    // The head transform (column-major 4x4) and the implicit solve's blend (SUBSTEP_HEAD_BYTES
    // together), then the placed colliders.
    s.push_str(
        "struct Substep {\n    head: mat4x4<f32>,\n    blend: vec4<f32>,\n    colliders: array<Collider, NC>,\n}\n",
    );
    s
}
