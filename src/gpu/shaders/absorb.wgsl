// Held water's laws that several modules use: the saturation (held water, liquid bridges) and
// absorption's demand (physics/wet.rs `absorb_weight`, `absorb_demand`; docs/WET_MODEL.md §2),
// shared by the wet hair module, which asks (in adhesion), and the held-water module, which
// grants (in absorb): both compute each demand from the same inputs with this one function.

// wet::saturation: held over capacity (0 where a point holds nothing).
fn saturation(q: u32, c: u32) -> f32 {
    if (c > 0u) {
        return f32(q) / f32(c);
    }
    return 0.0;
}

// wet::hold_room: a point's room below its hold limit c, holding q.
fn hold_room(q: u32, c: u32) -> u32 {
    return c - min(q, c);
}

// 1 within r_min of the particle, falling linearly to 0 at r_max.
fn absorb_weight(d: f32) -> f32 {
    return clamp((P.r_max - d) / (P.r_max - P.r_min), 0.0, 1.0);
}

// wet::absorb_share: the length of hair point i stands for (half of each rest segment it
// ends) over ABSORB_LENGTH.
fn absorb_share(i: u32) -> f32 {
    return rest_around(i) * ABSORB_SHARE_SCALE;
}

// wet::absorb_take_at: what point i takes of a particle within r_min this substep, in
// proportion to the hair it stands for: its own (absorb_share) times its bundle's strands
// (bundle_at, generated per module: 1 but in a guide groom, physics/bundles.rs).
fn absorb_take_at(i: u32) -> f32 {
    return min(P.absorb_take * (absorb_share(i) * bundle_at(i)), 1.0);
}

// What a hair point `sat` full (its water over its hold limit, the wetness it shows) at
// squared distance `d2` asks of a particle holding `q` quanta in a substep, `take` its
// absorb_take_at: floor(take q weight (1 - sat)); nothing from an empty particle or for a full
// point.
fn absorb_demand(q: u32, d2: f32, sat: f32, take: f32) -> u32 {
    if (q == 0u || sat >= 1.0) {
        return 0u;
    }
    return u32(floor(take * f32(q) * absorb_weight(sqrt(d2)) * max(1.0 - sat, 0.0)));
}

// Point i's word and bit among the marks after the particles' absorption records
// (buffers::absorb_words::near_bits): the hair kernel sets the bit where a particle was
// within r_max, and absorb visits only the points marked, clearing each.
fn near_word(i: u32) -> u32 {
    return P.capacity * ABS_WORDS + i / 32u;
}

fn near_bit(i: u32) -> u32 {
    return 1u << (i % 32u);
}
