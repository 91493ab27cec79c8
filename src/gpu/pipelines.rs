//! Shader modules and pipelines assembled from the scene: each module is the shared prelude
//! plus only the passes the scene uses, so a dry scene's shader has no adhesion code and its
//! pipelines bind no water buffer. The hair substep's body is written from the pass list, the
//! same list [`crate::plan::pass_list`] gives the CPU backend.

use crate::plan::Pass;

const COMMON: &str = include_str!("shaders/common.wgsl");
const GRID: &str = include_str!("shaders/grid.wgsl");
const GRID_MARKS: &str = include_str!("shaders/grid_marks.wgsl");
const HAIR: &str = include_str!("shaders/hair.wgsl");
const EXPLICIT_POINT: &str = include_str!("shaders/explicit_point.wgsl");
const ADHESION: &str = include_str!("shaders/adhesion.wgsl");
const REACTION32: &str = include_str!("shaders/reaction32.wgsl");
const REACTION64: &str = include_str!("shaders/reaction64.wgsl");
const REACTION_GATHERED: &str = include_str!("shaders/reaction_gathered.wgsl");
const REACTIONS: &str = include_str!("shaders/reactions.wgsl");
const WET_LAYOUT: &str = include_str!("shaders/wet_layout.wgsl");
const PAIR: &str = include_str!("shaders/pair.wgsl");
const WATER: &str = include_str!("shaders/water.wgsl");
const PILES: &str = include_str!("shaders/piles.wgsl");
const OUTPUT: &str = include_str!("shaders/output.wgsl");
const VERTEX: &str = include_str!("shaders/vertex.wgsl");
const FOLLOW: &str = include_str!("shaders/follow.wgsl");
const GUIDE_FRAMES: &str = include_str!("shaders/guide_frames.wgsl");
const WRITE_FOLLOWERS: &str = include_str!("shaders/write_followers.wgsl");
const WATER_OUTPUT: &str = include_str!("shaders/water_output.wgsl");
const SDF: &str = include_str!("shaders/sdf.wgsl");
const ROOTS: &str = include_str!("shaders/roots.wgsl");
const ROOT_FRAME: &str = include_str!("shaders/root_frame.wgsl");
const VOLUME: &str = include_str!("shaders/volume.wgsl");
const VOLUME_SPREAD: &str = include_str!("shaders/volume_spread.wgsl");
const VOLUME_RESPOND: &str = include_str!("shaders/volume_respond.wgsl");
const SDF_HAIR: &str = include_str!("shaders/sdf_hair.wgsl");
const SDF_WATER: &str = include_str!("shaders/sdf_water.wgsl");
const IMPLICIT: &str = include_str!("shaders/implicit.wgsl");
const BDF2: &str = include_str!("shaders/bdf2.wgsl");

/// Backward Euler's start: the state as it is (BDF2's is `shaders/bdf2.wgsl`).
const EULER_START: &str = "fn start_of(idx: u32, st: State) -> State {\n    return st;\n}\n";
const HELD: &str = include_str!("shaders/held.wgsl");
const ABSORB: &str = include_str!("shaders/absorb.wgsl");
const REST_SEGMENTS: &str = include_str!("shaders/rest_segments.wgsl");
const SCAN: &str = include_str!("shaders/scan.wgsl");
const COUNTING_SCAN: &str = include_str!("shaders/counting_scan.wgsl");
const BRIDGES: &str = include_str!("shaders/bridges.wgsl");
const COHESION: &str = include_str!("shaders/cohesion.wgsl");

/// Compile-time constants of one scene's shaders.
#[derive(Clone, Copy, Debug)]
pub struct SceneConsts {
    /// Axial (true) or relative (false) spring damping.
    pub axial: bool,
    /// Colliders per substep.
    pub colliders: u32,
    /// The scene has bend springs.
    pub bend: bool,
    /// Points of the longest strand (sizes implicit Euler's per-strand system).
    pub max_points: u32,
    /// Newton iterations of implicit Euler.
    pub iterations: u32,
    /// The implicit solve starts from BDF2's blend (and binds its history), and the explicit
    /// forces are taken at `x + h v` (`explicit_point` in hair.wgsl).
    pub bdf2: bool,
    /// Skinned roots: pinned points read their target from their record (`roots.wgsl`).
    pub roots: bool,
    /// The device adds 64-bit integers atomically (`reaction64.wgsl`, else `reaction32.wgsl`).
    pub atomic64: bool,
    /// The particles gather their reactions (`reaction_gathered.wgsl`, `reactions.wgsl`)
    /// instead of the hair points adding them (`WETHAIR_GPU_REACTIONS=gather`).
    pub gathered: bool,
    /// A guide groom's point count (0: none), whose strands stand for bundles
    /// (`physics/bundles.rs`): the absorption scratch holds each point's bundle
    /// ([`bundle_at`]), and with held water the held dry masses each point's quantum.
    pub bundle_points: u32,
}

/// How a module reads the absorption scratch, where a guide groom's bundles are kept.
#[derive(Clone, Copy, PartialEq)]
enum Scratch {
    /// Not bound: every bundle is 1 to it.
    None,
    /// Bound as `array<atomic<u32>>` (the hair and held-water modules).
    Atomic,
    /// Bound as `array<u32>` (the particles' gather, `reactions.wgsl`).
    Plain,
}

/// absorb.wgsl's `bundle_at(i)`: point i's bundle in a guide groom, read as f32 bits from the
/// absorption scratch at `buffers::absorb_words::bundles_at` (written by
/// `GpuBackend::write_bundles`); else 1. What absorption asks by, and eq. 2's reaction
/// pulls with.
fn bundle_at(c: SceneConsts, scratch: Scratch) -> String {
    let near = super::buffers::absorb_words::near_bits(c.bundle_points);
    let at = format!("select(0u, P.capacity * ABS_WORDS + {near}u, P.absorbs != 0u) + i");
    let word = match scratch {
        Scratch::Atomic => format!("atomicLoad(&absorb_scratch[{at}])"),
        Scratch::Plain => format!("absorb_scratch[{at}]"),
        Scratch::None => String::new(),
    };
    match (c.bundle_points, scratch) {
        (0, _) | (_, Scratch::None) => "fn bundle_at(i: u32) -> f32 {\n    return 1.0;\n}\n".into(),
        _ => format!("fn bundle_at(i: u32) -> f32 {{\n    return bitcast<f32>({word});\n}}\n"),
    }
}

/// The scene's constants, the generated prelude (shared constants and structs), and the
/// helpers every module uses.
fn prelude(c: SceneConsts) -> String {
    format!(
        "const AXIAL: bool = {};\nconst BEND: bool = {};\nconst ROOTS: bool = {};\nconst BDF2: bool = {};\nconst N_COLLIDERS: u32 = {}u;\nconst NC: u32 = {}u;\n{}{COMMON}\n",
        c.axial,
        c.bend,
        c.roots,
        c.bdf2,
        c.colliders,
        c.colliders.max(1),
        super::wgsl::prelude(),
    )
}

/// Whether implicit Euler needs the `hair_forces` kernel (drag, adhesion or cohesion present).
pub fn has_forces(passes: &[Pass]) -> bool {
    passes
        .iter()
        .any(|p| matches!(p, Pass::Drag | Pass::Adhesion | Pass::Cohesion))
}

/// Pass cohesion's kernel and the line that adds its parked pull (scenes with bridges only).
fn cohesion(passes: &[Pass]) -> &'static str {
    if passes.contains(&Pass::Cohesion) {
        COHESION
    } else {
        ""
    }
}

/// Adds the pull pass cohesion parked in this point's output velocity, where it parked one
/// (w = 1); elsewhere zero, as an unbridged point's pull was when cohesion wrote every point.
const ADD_COHESION: &str =
    "    let parked = state_out[i].v;\n    f += select(vec3<f32>(0.0), parked.xyz, parked.w != 0.0);\n";

/// Pass adhesion in a hair kernel, taken at `point` (`x`, or `explicit_point(s)` in
/// `hair_forces`): the pull, the wetting, and with absorption the mark that sends the point to
/// the absorb pass.
fn adhesion_call(point: &str) -> String {
    format!(
        "    var near = 0.0;\n    f += adhesion(i, {point}, wet, &near);\n    wet += (1.0 - wet) * P.wet_gain * near;\n    \
         if (near != 0.0 && P.absorbs != 0u) {{\n        mark_near(i);\n    }}\n"
    )
}

/// The hair module: the substep kernel for `passes` (and water_integrate when wet).
pub fn hair_source(c: SceneConsts, passes: &[Pass]) -> String {
    let wet = passes.contains(&Pass::Adhesion);
    if passes.contains(&Pass::ImplicitSolve) {
        return implicit_source(c, passes);
    }
    let mut body = String::new();
    let adhesion_at_x = adhesion_call("x");
    for p in passes {
        body.push_str(match p {
            Pass::Drag => "    drag(i, v, &f);\n",
            Pass::StretchSprings => "    stretch_springs(i, pt, x, v, &f);\n",
            Pass::BendSprings => "    bend_springs(i, pt, x, v, &f);\n",
            Pass::Adhesion => &adhesion_at_x,
            Pass::Cohesion => ADD_COHESION,
            Pass::Integrate => "    integrate(pt, &x, &v, f);\n",
            Pass::Collide => {
                "    if (pt.inv_mass > 0.0) {\n        for (var c = 0u; c < N_COLLIDERS; c++) {\n            \
                 collide(&x, &v, S.colliders[c], P.friction);\n        }\n    }\n"
            }
            // Dispatched as their own kernels (or not ported: the backend refuses them).
            Pass::WaterGrid
            | Pass::WaterIntegrate
            | Pass::WaterCull
            | Pass::Dry
            | Pass::HairGrid
            | Pass::Volume
            | Pass::Absorb
            | Pass::Flow
            | Pass::Drip
            | Pass::ImplicitSolve
            | Pass::ProjectConstraints => "",
        });
    }
    format!(
        "{}{REST_SEGMENTS}{HAIR}\n{EXPLICIT_POINT}\n{}{}\n// Passes of this scene, in the CPU's order.\n@compute @workgroup_size(WG)\n\
         fn hair_substep(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,\n\
         \x20               @builtin(local_invocation_index) lid: u32) {{\n    let i = linear_id(wid, nwg, lid);\n\
         \x20   if (i >= P.points) {{\n        return;\n    }}\n    let pt = points[i];\n    let s = state_in[i];\n\
         \x20   var x = s.x.xyz;\n    var v = s.v.xyz;\n    var wet = s.x.w;\n    var f = vec3<f32>(0.0);\n\
         {body}    check(i, x, v);\n    state_out[i] = State(vec4<f32>(x, wet), vec4<f32>(v, 0.0));\n}}\n",
        prelude(c),
        if wet { adhesion(c) } else { String::new() },
        cohesion(passes),
    )
}

/// Eq. 2, absorption's demand, and the grid queries they make (wet scenes only), with the
/// particles' reaction sums in the device's widest atomic integers, or gathered by the
/// particles.
fn adhesion(c: SceneConsts) -> String {
    // The gathered form's records follow the `wet` buffer's layout, which the particles'
    // side shares.
    let (layout, reaction) = match (c.gathered, c.atomic64) {
        (true, _) => (WET_LAYOUT, REACTION_GATHERED),
        (false, true) => ("", REACTION64),
        (false, false) => ("", REACTION32),
    };
    let bundles = bundle_at(c, Scratch::Atomic);
    format!("{GRID}\n{GRID_MARKS}\n{bundles}{ABSORB}\n{layout}\n{reaction}\n{PAIR}\n{ADHESION}")
}

/// The module where the particles gather their reactions (`SceneConsts::gathered`): the
/// records' sort and the gather. Absorption's laws read `points` only in functions it does
/// not call, so that binding is declared and never bound.
pub fn reactions_source(c: SceneConsts) -> String {
    format!(
        "{}@group(1) @binding(0) var<storage, read> points: array<Point>;\n{REST_SEGMENTS}{GRID}\n{GRID_MARKS}\n{SCAN}\n{COUNTING_SCAN}\n{}{ABSORB}\n{WET_LAYOUT}\n{PAIR}\n{REACTIONS}",
        prelude(c),
        bundle_at(c, Scratch::Plain)
    )
}

/// Implicit Euler's (and BDF2's) hair module: `hair_forces` (adhesion, wetting, cohesion; per
/// point, only when the scene has them) writes the explicit forces into state_out, then
/// `implicit_solve` (per strand, from BDF2's blend when it runs) integrates and collides.
fn implicit_source(c: SceneConsts, passes: &[Pass]) -> String {
    let wet = passes.contains(&Pass::Adhesion);
    let forces = has_forces(passes);
    let mut out = format!(
        "{}{REST_SEGMENTS}{HAIR}\n{EXPLICIT_POINT}\n{}{}\n{}\nconst P_MAX: u32 = {}u;\nconst ITERATIONS: u32 = {}u;\nconst HAS_FORCES: bool = {forces};\n\
         const COLLIDE: bool = {};\n{IMPLICIT}\n",
        prelude(c),
        if wet { adhesion(c) } else { String::new() },
        cohesion(passes),
        if c.bdf2 { BDF2 } else { EULER_START },
        c.max_points.max(2),
        c.iterations.max(1),
        passes.contains(&Pass::Collide),
    );
    if forces {
        let mut body = String::new();
        if wet {
            body.push_str(&adhesion_call("explicit_point(s)"));
        }
        if passes.contains(&Pass::Cohesion) {
            body.push_str(ADD_COHESION);
        }
        out.push_str(&format!(
            "// Explicit forces of this scene, in the CPU's order, parked in state_out.\n@compute @workgroup_size(WG)\n\
             fn hair_forces(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,\n\
             \x20              @builtin(local_invocation_index) lid: u32) {{\n    let i = linear_id(wid, nwg, lid);\n\
             \x20   if (i >= P.points) {{\n        return;\n    }}\n    let s = state_in[i];\n    let x = s.x.xyz;\n\
             \x20   let v = s.v.xyz;\n    var wet = s.x.w;\n    var f = vec3<f32>(0.0);\n{body}\
             \x20   state_out[i] = State(vec4<f32>(f, wet), vec4<f32>(0.0));\n}}\n"
        ));
    }
    out
}

/// The water module (grid build, append, cull).
pub fn water_source(c: SceneConsts) -> String {
    format!("{}{GRID}\n{SCAN}\n{COUNTING_SCAN}\n{WATER}", prelude(c))
}

/// The module that coalesces drops that meet (scenes where `SimParams::coalesces`).
pub fn piles_source(c: SceneConsts) -> String {
    format!("{}{PILES}", prelude(c))
}

/// The held-water module (scenes with held water only) for a groom of `points` points (its
/// buffers' length: the hold limits, and in a guide groom the bundles and quanta, follow each
/// point's value at that offset, whatever the points stepped now).
pub fn held_source(c: SceneConsts, points: u32) -> String {
    format!(
        "{}const HELD_POINTS: u32 = {points}u;\nconst HELD_BUNDLES: bool = {};\n{SCAN}\n{HELD}\n{GRID}\n{GRID_MARKS}\n{REST_SEGMENTS}{}{ABSORB}\n{EXPLICIT_POINT}",
        prelude(c),
        c.bundle_points > 0,
        bundle_at(c, Scratch::Atomic),
    )
}

/// The liquid bridges' module (pass hair_grid; scenes with bridges only) over a hashed grid of
/// `buckets` buckets (a power of two, a multiple of the scan block), for `points` hair points
/// (the bridge buffer's size: its flags follow its masks).
pub fn bridges_source(c: SceneConsts, buckets: u32, points: u32) -> String {
    format!(
        "{}const BRIDGE_BUCKETS: u32 = {buckets}u;\nconst BRIDGE_BLOCKS: u32 = {}u;\nconst BRIDGE_POINTS: u32 = {points}u;\n\
         {SCAN}\n{COUNTING_SCAN}\n{REST_SEGMENTS}{}{ABSORB}\n{BRIDGES}",
        prelude(c),
        buckets / super::buffers::SCAN_BLOCK,
        bundle_at(c, Scratch::None),
    )
}

/// The vertex output module.
pub fn output_source(c: SceneConsts) -> String {
    format!("{}{VERTEX}{OUTPUT}", prelude(c))
}

/// The guides' frames pass (`guide_frames`; scenes with guides only).
pub fn guide_frames_source(c: SceneConsts) -> String {
    format!("{}{FOLLOW}{GUIDE_FRAMES}", prelude(c))
}

/// The followers' output pass (`write_followers`; scenes with guides only).
pub fn write_followers_source(c: SceneConsts) -> String {
    format!("{}{FOLLOW}{ROOT_FRAME}{VERTEX}{WRITE_FOLLOWERS}", prelude(c))
}

/// The SDF colliders' hair pass, for a scene with `nsdf` SDFs.
pub fn sdf_hair_source(c: SceneConsts, nsdf: usize) -> String {
    format!("{}const NSDF: u32 = {nsdf}u;\n{SDF}{SDF_HAIR}", prelude(c))
}

/// The SDF colliders' particle pass, for a scene with `nsdf` SDFs.
pub fn sdf_water_source(c: SceneConsts, nsdf: usize) -> String {
    format!("{}const NSDF: u32 = {nsdf}u;\n{SDF}{SDF_WATER}", prelude(c))
}

/// Hair-hair volume's spreading pass (`volume_spread`).
pub fn volume_spread_source(c: SceneConsts) -> String {
    format!("{}{VOLUME}{VOLUME_SPREAD}", prelude(c))
}

/// Hair-hair volume's response pass (`volume_respond`).
pub fn volume_respond_source(c: SceneConsts) -> String {
    format!("{}{VOLUME}{VOLUME_RESPOND}", prelude(c))
}

/// Skinned roots' passes `pin_roots` and `carry_roots`.
pub fn roots_source(c: SceneConsts) -> String {
    format!("{}{ROOT_FRAME}{ROOTS}", prelude(c))
}

/// The shared water output module (host-shared devices that draw the particles).
pub fn water_output_source(c: SceneConsts) -> String {
    format!("{}{WATER_OUTPUT}", prelude(c))
}

/// Compiles WGSL; errors surface through the device's error handler.
pub fn module(dev: &wgpu::Device, label: &str, src: &str) -> wgpu::ShaderModule {
    dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    })
}

/// One bind group layout entry kind.
#[derive(Clone, Copy)]
pub enum Slot {
    /// A uniform buffer.
    Uniform,
    /// A uniform buffer bound with a dynamic offset.
    UniformDynamic,
    /// A read-only storage buffer.
    Read,
    /// A read-write storage buffer.
    ReadWrite,
}

/// A compute bind group layout with `slots` at bindings 0, 1, ...
pub fn layout(dev: &wgpu::Device, label: &str, slots: &[Slot]) -> wgpu::BindGroupLayout {
    let numbered: Vec<(u32, Slot)> = slots.iter().enumerate().map(|(i, &s)| (i as u32, s)).collect();
    layout_at(dev, label, &numbered)
}

/// A compute bind group layout with each slot at its own binding number: for a kernel that
/// binds only some of a group its module declares (to stay within eight storage buffers).
pub fn layout_at(dev: &wgpu::Device, label: &str, slots: &[(u32, Slot)]) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = slots
        .iter()
        .map(|&(binding, s)| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: match s {
                    Slot::Uniform | Slot::UniformDynamic => wgpu::BufferBindingType::Uniform,
                    Slot::Read => wgpu::BufferBindingType::Storage { read_only: true },
                    Slot::ReadWrite => wgpu::BufferBindingType::Storage { read_only: false },
                },
                has_dynamic_offset: matches!(s, Slot::UniformDynamic),
                min_binding_size: None,
            },
            count: None,
        })
        .collect();
    dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// A bind group over whole buffers (or, for a dynamic uniform, `dyn_size` bytes of it).
pub fn bind(
    dev: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
    dyn_size: Option<(usize, u64)>,
) -> wgpu::BindGroup {
    let resources: Vec<wgpu::BindingResource> = buffers
        .iter()
        .enumerate()
        .map(|(i, b)| match dyn_size {
            Some((at, size)) if at == i => wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: b,
                offset: 0,
                size: std::num::NonZeroU64::new(size),
            }),
            _ => b.as_entire_binding(),
        })
        .collect();
    bind_resources(dev, label, layout, resources)
}

/// A bind group whose binding `i` is `resources[i]` (for ranges of buffers; [`bind`] for
/// whole ones).
pub fn bind_resources(
    dev: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: Vec<wgpu::BindingResource>,
) -> wgpu::BindGroup {
    let numbered = resources.into_iter().enumerate().map(|(i, r)| (i as u32, r)).collect();
    bind_at(dev, label, layout, numbered)
}

/// A bind group with each resource at its own binding number (a [`layout_at`] layout's).
pub fn bind_at(
    dev: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: Vec<(u32, wgpu::BindingResource)>,
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .into_iter()
        .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource })
        .collect();
    dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// Compute pipelines of one module sharing one pipeline layout.
pub fn pipelines(
    dev: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layouts: &[&wgpu::BindGroupLayout],
    entries: &[&str],
) -> Vec<wgpu::ComputePipeline> {
    let bgls: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    pipelines_sparse(dev, module, &bgls, entries)
}

/// Like [`pipelines`], with unused bind group slots left `None`.
pub fn pipelines_sparse(
    dev: &wgpu::Device,
    module: &wgpu::ShaderModule,
    bgls: &[Option<&wgpu::BindGroupLayout>],
    entries: &[&str],
) -> Vec<wgpu::ComputePipeline> {
    let pl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: bgls,
        immediate_size: 0,
    });
    entries
        .iter()
        .map(|e| {
            dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(e),
                layout: Some(&pl),
                module,
                entry_point: Some(e),
                compilation_options: Default::default(),
                cache: None,
            })
        })
        .collect()
}
