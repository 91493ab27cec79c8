// Shared by every wethair compute module: the per-step parameters, the per-point data, and
// the helpers every pass uses. `pipelines.rs` prepends the scene's constants (AXIAL, BEND,
// DRAG, N_COLLIDERS, WG) and appends only the passes the scene needs.

// Per-step constants (mirrors `gpu::buffers::Params`).
struct Params {
    h: f32,
    inv_h: f32,
    drag: f32,
    friction: f32,
    g: vec4<f32>,
    points: u32,
    strands: u32,
    stretch_k: f32,
    stretch_c: f32,
    bend_k: f32,
    bend_c: f32,
    r_min: f32,
    r_max: f32,
    adhesion: f32,
    wet_gain: f32,
    particle_inv_mass: f32,
    water_drag: f32,
    capacity: u32,
    stride: u32,
    pos_off: u32,
    tan_off: u32,
    wet_off: u32,
    incoming: u32,
    max_cells: u32,
    domain_r2: f32,
    domain_center: vec4<f32>,
}

// Constant data of one hair point (mirrors `gpu::buffers::PointGpu`).
struct Point {
    rest: vec3<f32>,        // rest position in head space (pinned points' target)
    inv_mass: f32,          // 0 for pinned points
    rest_stretch: f32,      // rest length of the spring to point + 1
    rest_bend: f32,         // rest length of the spring to point + 2
    first: u32,             // the strand's first point
    last: u32,              // the strand's last point
}

// Dynamic state of one hair point; `x.w` is its wetness.
struct State {
    x: vec4<f32>,
    v: vec4<f32>,
}

// A water particle (position, velocity; w unused).
struct Particle {
    x: vec4<f32>,
    v: vec4<f32>,
}

// A collider placed for one substep: a capsule from `a.xyz` along `ab.xyz`, radius `a.w`,
// `ab.w = 1 / |ab|^2` (0 for a sphere).
struct Collider {
    a: vec4<f32>,
    ab: vec4<f32>,
}

// Linear invocation index over a 2D dispatch (x up to 65,535 workgroups per row).
fn linear_id(wid: vec3<u32>, nwg: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * nwg.x + wid.x) * WG + lid;
}

// True for inf and NaN (a bit test: `x != x` may be folded away by shader compilers).
fn non_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) == 0x7f800000u;
}

// Pushes a point out of a placed collider (physics/collide.rs, `collide_row` per lane):
// moved to the surface, velocity into the surface removed, tangential part scaled.
fn collide(x: ptr<function, vec3<f32>>, v: ptr<function, vec3<f32>>, c: Collider, friction: f32) {
    let p = *x - c.a.xyz;
    let t = clamp(dot(p, c.ab.xyz) * c.ab.w, 0.0, 1.0);
    let axis = c.a.xyz + c.ab.xyz * t;
    let d = *x - axis;
    let d2 = dot(d, d);
    if (d2 >= c.a.w * c.a.w) {
        return;
    }
    var n = vec3<f32>(0.0, 0.0, 1.0);
    if (d2 > 1e-24) {
        n = d * (1.0 / sqrt(d2));
    }
    let vv = *v;
    let vn = dot(vv, n);
    let into = min(vn, 0.0);
    let tang = vv - n * vn;
    *x = axis + n * c.a.w;
    *v = vv - n * into - tang * friction;
}
