// Helpers every wethair compute module uses. `pipelines.rs` prepends the scene's constants
// (AXIAL, BEND, N_COLLIDERS, NC) and the generated prelude (gpu/wgsl.rs: the shared constants
// and the structs Params, Point, State, Particle, Collider, Substep, laid out as the Rust
// records), and appends only the passes the scene needs.

// Linear invocation index over a 2D dispatch (x up to 65,535 workgroups per row).
fn linear_id(wid: vec3<u32>, nwg: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * nwg.x + wid.x) * WG + lid;
}

// True for inf and NaN (a bit test: `x != x` may be folded away by shader compilers).
fn non_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) == 0x7f800000u;
}

// Trilinear interpolation (physics/trilinear.rs): the value at fractions f of the cell whose
// corner values are c (x fastest), and its gradient per cell (yzw).
fn trilinear(c: array<f32, 8>, f: vec3<f32>) -> vec4<f32> {
    let x00 = c[0] + (c[1] - c[0]) * f.x;
    let x10 = c[2] + (c[3] - c[2]) * f.x;
    let x01 = c[4] + (c[5] - c[4]) * f.x;
    let x11 = c[6] + (c[7] - c[6]) * f.x;
    let y0 = x00 + (x10 - x00) * f.y;
    let y1 = x01 + (x11 - x01) * f.y;
    let d = y0 + (y1 - y0) * f.z;
    let e0 = (c[1] - c[0]) + ((c[3] - c[2]) - (c[1] - c[0])) * f.y;
    let e1 = (c[5] - c[4]) + ((c[7] - c[6]) - (c[5] - c[4])) * f.y;
    let dx = e0 + (e1 - e0) * f.z;
    let dy = (x10 - x00) + ((x11 - x01) - (x10 - x00)) * f.z;
    return vec4<f32>(d, dx, dy, y1 - y0);
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
    if (d2 > ON_AXIS_D2) {
        n = d * (1.0 / sqrt(d2));
    }
    // Relative to the surface where it moves (collide.rs `respond_moving`).
    let vc = c.va.xyz + c.vab.xyz * t;
    let vv = *v - vc;
    let vn = dot(vv, n);
    let into = min(vn, 0.0);
    let tang = vv - n * vn;
    *x = axis + n * c.a.w;
    *v = vc + (vv - n * into - tang * friction);
}

// The high word to add to a 64-bit fixed-point sum kept as two u32 words, after `v.x` was
// added to a low word that held `old`: `v.y` plus the carry out of the low word. The adds of
// adhesion's reactions and of the volume's grid and workgroup table all take it, and skip
// their second atomic when it is 0.
fn carried_high(old: u32, v: vec2<u32>) -> u32 {
    return v.y + select(0u, 1u, old + v.x < old);
}

// Two's-complement negation of a 64-bit word pair (lo, hi): adhesion's reaction sums and the
// piles' fixed-point sums.
fn fixed_neg(a: vec2<u32>) -> vec2<u32> {
    return vec2<u32>(~a.x + 1u, ~a.y + select(0u, 1u, a.x == 0u));
}

// A cell's coordinates folded in one by one by odd multipliers and shifts (physics/hash_grid.rs
// `bucket_at` before its mask): the hashed grids of the water and of the liquid bridges.
fn hash_cell(c: vec3<i32>) -> u32 {
    var h = bitcast<u32>(c.x) * 0x9e3779b1u;
    h ^= h >> 16u;
    h = (h ^ bitcast<u32>(c.y)) * 0x85ebca77u;
    h ^= h >> 13u;
    h = (h ^ bitcast<u32>(c.z)) * 0xc2b2ae3du;
    h ^= h >> 16u;
    return h;
}
