// The particles' reaction sums as 64-bit integers (adhesion.wgsl), where the device adds them
// atomically: the same memory as reaction32.wgsl's word pairs (a little-endian u64 is its low
// word, then its high word), one add a component, and nothing read back, so a point never
// waits on the memory for it. With 100,000 particles in the paper scene the pairs' adds that
// waited for their carry were 94% of the hair kernel (14.5 of 15.4 ms a step on an H200).

@group(1) @binding(1) var<storage, read_write> water_force: array<atomic<u64>>;

// Adds v (low word, high word) to component a of particle k.
fn add_reaction(k: u32, a: u32, v: vec2<u32>) {
    atomicAdd(&water_force[(WATER_FORCE_WORDS * k) / 2u + a], (u64(v.y) << 32u) | u64(v.x));
}

// Component a of particle k's sum as (low word, high word); u32() of a u64 keeps its low 32
// bits.
fn reaction_sum(k: u32, a: u32) -> vec2<u32> {
    let s = atomicLoad(&water_force[(WATER_FORCE_WORDS * k) / 2u + a]);
    return vec2<u32>(u32(s), u32(s >> 32u));
}

// Adds v to particle k's sum of how stiffly the hair holds it (word 6, the fourth u64's low
// word: the sum stays below 2^32, so its high word stays 0).
fn add_stiffness(k: u32, v: u32) {
    atomicAdd(&water_force[(WATER_FORCE_WORDS * k) / 2u + 3u], u64(v));
}

// Particle k's sum of how stiffly the hair holds it, STIFFNESS_SCALE units.
fn stiffness_sum(k: u32) -> u32 {
    return u32(atomicLoad(&water_force[(WATER_FORCE_WORDS * k) / 2u + 3u]));
}

// Particle k's sums back to zero, once water_integrate has read them (the next build may give
// the slot to another particle).
fn clear_reactions(k: u32) {
    for (var a = 0u; a < 4u; a++) {
        atomicStore(&water_force[(WATER_FORCE_WORDS * k) / 2u + a], u64(0u));
    }
}

// The scatter form: the hair points add the reactions above, and leave no record for a
// gather (reaction_gathered.wgsl).
const GATHERED: bool = false;

fn note_wet(i: u32, x: vec3<f32>, share: f32, sat: f32, take: f32, found: bool) {}
