// The water's hashed grid (physics/hash_grid.rs `HashGrid`): cells of side WATER_CELL_R r_max
// anywhere in space, their particles counted into a table of `G_BUCKETS` buckets (about two a
// particle), shared by the water module (which builds it) and the wet hair modules (which
// query it). A query walks cells as small as its reach however far the particles spread: the
// dense grid this replaces bounded its cells by the particles' box, and particles flung a
// metre off a head grew its cells to 8 r_max, where a hair point read 26 times the
// candidates it needs. Both bind the grid's words as `grid`; the G_* offsets come from the
// prelude.

// HashGrid::coord_of: the cell holding x (floor; beyond i32 saturates).
fn water_cell(x: vec3<f32>) -> vec3<i32> {
    return vec3<i32>(floor(x * bitcast<f32>(grid[G_INV])));
}

// HashGrid::bucket_of: the bucket listing cell c's particles (and those of cells that hash
// alike).
fn water_bucket(c: vec3<i32>) -> u32 {
    return hash_cell(c) & (grid[G_BUCKETS] - 1u);
}

// The slots [start, end) of the bucket of cell c.
fn cell_run(c: vec3<i32>) -> vec2<u32> {
    let b = water_bucket(c);
    return vec2<u32>(grid[G_START + b], grid[G_START + b + 1u]);
}

// Cell c's word and bit in a mark table of `words` words (physics/hash_marks.rs `mark_bit`).
fn mark_bit(c: vec3<i32>, words: u32) -> vec2<u32> {
    let i = hash_cell(c) & (32u * words - 1u);
    return vec2<u32>(i >> 5u, i & 31u);
}

// Whether a point at x may have a particle within reach (physics/hash_marks.rs `marked`):
// its cell's bit in the build's mark table, or true where the build has none. `mark_word`
// reads the table's words through the module's own binding (grid_marks.wgsl for the hair
// and held modules; the water module through its atomic view of that range).
fn marked(x: vec3<f32>) -> bool {
    let words = grid[G_MARKS];
    if (words == 0u) {
        return true;
    }
    let b = mark_bit(water_cell(x), words);
    return ((mark_word(b.x) >> b.y) & 1u) != 0u;
}

// The cells a query of radius r at x covers (r <= the cell's half side: at most 2 a side,
// 8 in all): false when no particle can be within r (the particles' box grown by r misses x,
// or x's cell is not marked), so points far from all water read no bucket.
struct Span {
    c0: vec3<i32>,
    c1: vec3<i32>,
}

fn near_span(x: vec3<f32>, r: f32, span: ptr<function, Span>) -> bool {
    if (grid[G_COUNT] == 0u) {
        return false;
    }
    let lo = vec3<f32>(bitcast<f32>(grid[G_LO]), bitcast<f32>(grid[G_LO + 1u]), bitcast<f32>(grid[G_LO + 2u]));
    let hi = vec3<f32>(bitcast<f32>(grid[G_HI]), bitcast<f32>(grid[G_HI + 1u]), bitcast<f32>(grid[G_HI + 2u]));
    if (any(x < lo - vec3<f32>(r)) || any(x > hi + vec3<f32>(r)) || !marked(x)) {
        return false;
    }
    (*span).c0 = water_cell(x - vec3<f32>(r));
    (*span).c1 = water_cell(x + vec3<f32>(r));
    return true;
}

// The span's cells, and its j-th (x slowest, as the CPU's queries nest).
fn span_cells(span: Span) -> i32 {
    let n = span.c1 - span.c0 + vec3<i32>(1);
    return n.x * n.y * n.z;
}

fn span_cell(span: Span, j: i32) -> vec3<i32> {
    let n = span.c1 - span.c0 + vec3<i32>(1);
    return span.c0 + vec3<i32>(j / (n.y * n.z), (j / n.z) % n.y, j % n.z);
}

// Whether the particle at y, found through cell c's bucket, lies in c: a bucket also lists
// the particles of other cells that hash alike, and two cells of one span may share a
// bucket, so a particle within reach counts only through its own cell (as
// HashGrid::for_each_near compares coordinates).
fn in_cell(y: vec3<f32>, c: vec3<i32>) -> bool {
    return all(water_cell(y) == c);
}
