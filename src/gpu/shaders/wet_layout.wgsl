// Where the particles gather their reactions: the layout of the `wet` buffer
// (buffers::wet_words), shared by the hair's side (reaction_gathered.wgsl), which writes the
// counts and records, and the particles' side (reactions.wgsl), which reads them. The
// particles' sums come first (WATER_FORCE_WORDS a particle, for the capacity), then a count
// per bucket (P.max_buckets), then a record of WET_RECORD words a hair point.

// The first word of the counts.
fn wet_counts_at() -> u32 {
    return WATER_FORCE_WORDS * P.capacity;
}

// The first word of point i's record.
fn wet_record_at(i: u32) -> u32 {
    return wet_counts_at() + P.max_buckets + WET_RECORD * i;
}
