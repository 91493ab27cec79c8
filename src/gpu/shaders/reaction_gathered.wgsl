// The particles' reaction sums gathered by the particles (reactions.wgsl) instead of added by
// the hair points: the hair kernel adds nothing to any particle. Each point that had a
// particle within reach this substep (its pairs are exactly the ones its adhesion summed)
// leaves a record: the place and weights its pulls were reckoned with, and its key (its
// water-grid bucket + 1; 0 for a point with no pair), counted into its bucket. reactions.wgsl
// then sorts the records by bucket and each particle sums its pairs' reactions itself, in
// the same 64-bit fixed point: the sums are the scatter form's to the bit, with no atomic add
// a pair (94% of the hair kernel with 100,000 particles on an H200, 2026-11-27).
//
// One buffer, `wet` (laid out in wet_layout.wgsl), holds it all, so the hair kernel binds no
// more storage buffers than in the scatter form.

@group(1) @binding(1) var<storage, read_write> wet: array<atomic<u32>>;

const GATHERED: bool = true;

// The scatter form's adds: the particles gather their sums (reactions.wgsl).
fn add_reaction(k: u32, a: u32, v: vec2<u32>) {}

fn add_stiffness(k: u32, v: u32) {}

// Component a of particle k's sum as (low word, high word), as react_gather wrote it.
fn reaction_sum(k: u32, a: u32) -> vec2<u32> {
    let at = WATER_FORCE_WORDS * k + 2u * a;
    return vec2<u32>(atomicLoad(&wet[at]), atomicLoad(&wet[at + 1u]));
}

// Particle k's sum of how stiffly the hair holds it, STIFFNESS_SCALE units (word 6).
fn stiffness_sum(k: u32) -> u32 {
    return atomicLoad(&wet[WATER_FORCE_WORDS * k + 6u]);
}

// Nothing to clear: react_gather writes every held particle's sums each substep.
fn clear_reactions(k: u32) {}

// Point i's record for the particles' gather: `found` when a particle was within reach of x
// (the place its pulls were reckoned at), with the weight `share` its pulls took, its
// saturation `sat` and absorption take `take`; otherwise only its key, 0.
fn note_wet(i: u32, x: vec3<f32>, share: f32, sat: f32, take: f32, found: bool) {
    let at = wet_record_at(i);
    if (!found) {
        atomicStore(&wet[at], 0u);
        return;
    }
    let b = water_bucket(water_cell(x));
    atomicStore(&wet[at], b + 1u);
    atomicAdd(&wet[wet_counts_at() + b], 1u);
    let words = array<f32, 6>(x.x, x.y, x.z, share, sat, take);
    for (var w = 0u; w < 6u; w++) {
        atomicStore(&wet[at + 1u + w], bitcast<u32>(words[w]));
    }
}
