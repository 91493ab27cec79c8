// Hair-hair volume (physics/volume.rs): the head-space grid, trilinear weights, and integer
// quanta of mass and momentum as 64-bit two's-complement word pairs (low, high), so the sums
// are the same in any order. `pipelines.rs` appends the spread or the respond entry point.
// Each sample holds eight words: mass, then momentum x, y, z.

const VOLUME_WORDS: u32 = 8u;

@group(0) @binding(0) var<uniform> VU: VolumeStep;
@group(0) @binding(1) var<storage, read> points: array<Point>;
@group(0) @binding(2) var<storage, read_write> state: array<State>;

// World to head space (the step's start).
fn to_head(p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(VU.hx.xyz, p) + VU.hx.w, dot(VU.hy.xyz, p) + VU.hy.w, dot(VU.hz.xyz, p) + VU.hz.w);
}

// `VolumeGrid::locate`: the lower sample's index (w = 1 when inside) and the fractions.
fn volume_locate(p: vec3<f32>, f: ptr<function, vec3<f32>>) -> vec2<u32> {
    let g = (p - VU.origin.xyz) / VU.origin.w;
    let top = vec3<f32>(VU.dims.xyz - vec3<u32>(1u));
    if (!(all(g >= vec3<f32>(0.0)) && all(g <= top))) {
        return vec2<u32>(0u, 0u);
    }
    let i = min(vec3<u32>(g), VU.dims.xyz - vec3<u32>(2u));
    *f = g - vec3<f32>(i);
    return vec2<u32>(i.x + VU.dims.x * (i.y + VU.dims.y * i.z), 1u);
}

// Invocation i's cell and fractions, as `volume_locate`: w = 0 (nothing to do) for a pinned
// point, one past the hair, or one outside the grid.
fn volume_point(i: u32, f: ptr<function, vec3<f32>>) -> vec2<u32> {
    if (i >= VU.dims.w || points[i].inv_mass <= 0.0) {
        return vec2<u32>(0u, 0u);
    }
    return volume_locate(to_head(state[i].x.xyz), f);
}

// physics/volume.rs spread_mass: the dry share of a point's mass, which it spreads.
fn spread_mass(mass: f32, wetness: f32) -> f32 {
    return mass * (1.0 - clamp(wetness, 0.0, 1.0));
}

// `weights`: corner k's trilinear weight, x fastest.
fn volume_weight(f: vec3<f32>, k: u32) -> f32 {
    let wx = select(1.0 - f.x, f.x, (k & 1u) != 0u);
    let wy = select(1.0 - f.y, f.y, (k & 2u) != 0u);
    let wz = select(1.0 - f.z, f.z, (k & 4u) != 0u);
    return wx * wy * wz;
}

// Corner k's sample from the lower one.
fn volume_corner(base: u32, k: u32) -> u32 {
    let sx = VU.dims.x;
    let sy = VU.dims.x * VU.dims.y;
    return base + select(0u, 1u, (k & 1u) != 0u) + select(0u, sx, (k & 2u) != 0u) + select(0u, sy, (k & 4u) != 0u);
}

// Two's-complement negation of a word pair.
fn volume_neg(a: vec2<u32>) -> vec2<u32> {
    return vec2<u32>(~a.x + 1u, ~a.y + select(0u, 1u, a.x == 0u));
}

// `share`'s rounding: x (kg or kg·m/s) in quanta (`MASS_QUANTUM`, equal to the momentum's),
// as a word pair.
fn volume_quanta(x: f32) -> vec2<u32> {
    let m = round(abs(x) * VOLUME_QUANTA);
    let hi = floor(m / 4294967296.0);
    let r = vec2<u32>(u32(m - hi * 4294967296.0), u32(hi));
    return select(r, volume_neg(r), x < 0.0);
}

// A word pair back to f32 quanta (the magnitude converted, then the sign).
fn volume_value(a: vec2<u32>) -> f32 {
    let neg = (a.y & 0x80000000u) != 0u;
    let m = select(a, volume_neg(a), neg);
    let v = f32(m.y) * 4294967296.0 + f32(m.x);
    return select(v, -v, neg);
}
