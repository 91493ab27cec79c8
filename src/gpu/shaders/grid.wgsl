// The dense grid's header and eqs. 4-5 with clamping (physics/grid.rs `cell_of`, `index`),
// shared by the water module (which builds the grid) and the wet hair module (which queries
// it). Both bind the grid's words as `grid`; the G_* offsets come from the prelude.

fn grid_lo() -> vec3<f32> {
    return vec3<f32>(bitcast<f32>(grid[G_LO]), bitcast<f32>(grid[G_LO + 1u]), bitcast<f32>(grid[G_LO + 2u]));
}

fn grid_dims() -> vec3<i32> {
    return vec3<i32>(i32(grid[G_DIMS]), i32(grid[G_DIMS + 1u]), i32(grid[G_DIMS + 2u]));
}

// Eq. 4 with clamping: the cell holding p (any p: outside points clamp to the boundary cells).
fn cell_of(p: vec3<f32>, lo: vec3<f32>, inv_cell: f32, dims: vec3<i32>) -> vec3<i32> {
    let c = clamp((p - lo) * inv_cell, vec3<f32>(0.0), vec3<f32>(dims - vec3<i32>(1)));
    return min(max(vec3<i32>(c), vec3<i32>(0)), dims - vec3<i32>(1));
}

// The cells a query of radius r at x covers, as the CPU's `Grid::may_have_near` and query
// clamp them: false when no particle can be within r (the particles' box grown by r misses
// x; without this test clamping would send every far point to scan the boundary cells).
struct Span {
    c0: vec3<i32>,
    c1: vec3<i32>,
    dims: vec3<i32>,
}

fn near_span(x: vec3<f32>, r: f32, span: ptr<function, Span>) -> bool {
    if (grid[G_COUNT] == 0u) {
        return false;
    }
    let lo = grid_lo();
    let inv = bitcast<f32>(grid[G_INV]);
    let dims = grid_dims();
    let hi = lo + vec3<f32>(dims) * bitcast<f32>(grid[G_CELL]);
    if (any(x < lo - vec3<f32>(r)) || any(x > hi + vec3<f32>(r))) {
        return false;
    }
    (*span).c0 = cell_of(x - vec3<f32>(r), lo, inv, dims);
    (*span).c1 = cell_of(x + vec3<f32>(r), lo, inv, dims);
    (*span).dims = dims;
    return true;
}

// The slots [start, end) of the span's row (cx, cy): its cells c0.z..=c1.z are contiguous.
fn span_row(span: Span, cx: i32, cy: i32) -> vec2<u32> {
    let row = (cx * span.dims.y + cy) * span.dims.z;
    return vec2<u32>(grid[G_START + u32(row + span.c0.z)], grid[G_START + u32(row + span.c1.z) + 1u]);
}

// Eq. 5: the linear index of the cell holding p.
fn cell_index(p: vec3<f32>) -> u32 {
    let dims = grid_dims();
    let ci = cell_of(p, grid_lo(), bitcast<f32>(grid[G_INV]), dims);
    return u32((ci.x * dims.y + ci.y) * dims.z + ci.z);
}
