// Word w of the grid's mark table (grid.wgsl `marked`), for the modules that bind the whole
// `grid` buffer as words (hair and held water); the water module, which sets the table,
// reads it through its atomic view of that range instead (water.wgsl).
fn mark_word(w: u32) -> u32 {
    return grid[grid[G_MARK_AT] + w];
}
