// The particles' reaction sums as word pairs (adhesion.wgsl), for devices without 64-bit
// atomics: component a of particle k is the 64-bit two's-complement pair at
// WATER_FORCE_WORDS k + 2a (low word first).

@group(1) @binding(1) var<storage, read_write> water_force: array<atomic<u32>>;

// Adds v to component a of particle k: the carry out of the low word goes into the high one,
// so the pair ends as the exact sum in any order. The low add must read back the old word
// for the carry, so each waits for the memory's answer. Adding 0 changes nothing, so it is
// skipped: one pull is at most about 2^32 units, so the high word to add is mostly 0 (a
// positive pull without a carry, or a negative one's all-ones word cancelled by its carry).
fn add_reaction(k: u32, a: u32, v: vec2<u32>) {
    let at = WATER_FORCE_WORDS * k + 2u * a;
    let old = atomicAdd(&water_force[at], v.x);
    let hi = carried_high(old, v);
    if (hi != 0u) {
        atomicAdd(&water_force[at + 1u], hi);
    }
}

// Component a of particle k's sum as (low word, high word).
fn reaction_sum(k: u32, a: u32) -> vec2<u32> {
    let at = WATER_FORCE_WORDS * k + 2u * a;
    return vec2<u32>(atomicLoad(&water_force[at]), atomicLoad(&water_force[at + 1u]));
}

// Adds v to particle k's sum of how stiffly the hair holds it (word 6).
fn add_stiffness(k: u32, v: u32) {
    atomicAdd(&water_force[WATER_FORCE_WORDS * k + 6u], v);
}

// Particle k's sum of how stiffly the hair holds it, STIFFNESS_SCALE units.
fn stiffness_sum(k: u32) -> u32 {
    return atomicLoad(&water_force[WATER_FORCE_WORDS * k + 6u]);
}

// Particle k's sums back to zero, once water_integrate has read them (the next build may give
// the slot to another particle).
fn clear_reactions(k: u32) {
    for (var w = 0u; w < 7u; w++) {
        atomicStore(&water_force[WATER_FORCE_WORDS * k + w], 0u);
    }
}

// The scatter form: the hair points add the reactions above, and leave no record for a
// gather (reaction_gathered.wgsl).
const GATHERED: bool = false;

fn note_wet(i: u32, x: vec3<f32>, share: f32, sat: f32, take: f32, found: bool) {}
