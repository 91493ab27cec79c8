// Eq. 2's laws for one pair (physics/adhesion.rs), shared by the hair's side (adhesion.wgsl)
// and, where the particles gather their reactions, the particles' side (reactions.wgsl):
// both reckon each pair with these same functions from the same inputs, so the two sides'
// fixed-point sums are equal and opposite to the bit. The including module declares
// `sorted`, the particles in grid order.

// physics/adhesion.rs `profile_variable`: 1 at r_min, 0 halfway, -1 at r_max.
fn profile_variable(d: f32) -> f32 {
    return (2.0 * d - P.r_min - P.r_max) / (P.r_min - P.r_max);
}

// physics/adhesion.rs `pair_stiffness`: how stiffly one hair point holds a particle at squared
// distance d2, per unit of its strength, in the profile's steepest slopes: the larger of u and
// (r_max - r_min) g(d) / 4d, 0 where force_scale is 0.
fn pair_stiffness(d2: f32) -> f32 {
    if (d2 > P.r_max * P.r_max || d2 < MIN_DISTANCE * MIN_DISTANCE) {
        return 0.0;
    }
    let d = sqrt(d2);
    let u = profile_variable(d);
    // At most 1 (physics/adhesion.rs `stiffest_pair`), held there against rounding.
    let across = min((0.25 * (P.r_max - P.r_min)) * (1.0 - u * u) / d, 1.0);
    return max(u, across);
}

// How stiffly a point whose pulls take the weight `share` holds a particle at squared distance
// d2, in the units of the particle's sum (STIFFNESS_SCALE a unit of pair_stiffness).
fn stiffness_units(d2: f32, share: f32) -> u32 {
    return u32(pair_stiffness(d2) * share * STIFFNESS_SCALE + 0.5);
}

// Eq. 2's factor (physics/adhesion.rs `force_scale`): s g(d) / d within [MIN_DISTANCE, r_max],
// else 0, for a particle of strength s.
fn force_scale(d2: f32, s: f32) -> f32 {
    if (d2 > P.r_max * P.r_max || d2 < MIN_DISTANCE * MIN_DISTANCE) {
        return 0.0;
    }
    let d = sqrt(d2);
    let u = profile_variable(d);
    return s * (1.0 - u * u) / d;
}

// A force component as a 64-bit two's-complement integer (low word, high word) in units of
// the adhesion strength over FIXED_SCALE: 2.3e-10 of the largest pull one particle gives,
// finer than f32 near it, with room for 2^31 such pulls in one sum.
fn to_fixed(x: f32) -> vec2<u32> {
    let m = abs(x) * (FIXED_SCALE / P.adhesion);
    let hi = floor(m / 4294967296.0);
    // Exact: m and hi * 2^32 agree above the 24 bits an f32 holds.
    let r = vec2<u32>(u32(m - hi * 4294967296.0), u32(hi));
    return select(r, fixed_neg(r), x < 0.0);
}

fn fixed_add(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    let lo = a.x + b.x;
    return vec2<u32>(lo, a.y + b.y + select(0u, 1u, lo < a.x));
}

// Back to newtons: the magnitude converted, then the sign (converting the two words of a
// negative value apart would cancel catastrophically).
fn from_fixed(a: vec2<u32>) -> f32 {
    let neg = (a.y & 0x80000000u) != 0u;
    let m = select(a, fixed_neg(a), neg);
    let v = (f32(m.y) * 4294967296.0 + f32(m.x)) * (P.adhesion / FIXED_SCALE);
    return select(v, -v, neg);
}

// A particle's pull strength: eq. 2's s, with absorption the water it holds, or where drops
// that meet coalesce, s times the drops the source stands for (piles.wgsl; physics/adhesion.rs
// `Strength::of`).
fn strength_of(k: u32) -> f32 {
    if (P.absorbs != 0u) {
        return f32(sorted[k].mass) * P.strength_per_quantum;
    }
    if (P.pile_cell > 0.0) {
        return P.adhesion * f32(sorted[k].mass);
    }
    return P.adhesion;
}
