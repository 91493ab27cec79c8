// physics/lanes.rs `rest_segments`: the rest segments point i ends, summed, m (0 for a segment
// the strand does not have): what the hair a point stands for is reckoned from (its air drag,
// hair.wgsl `drag_at`; its share of eq. 2's pull, adhesion.wgsl `adhesion`; its share of
// absorption, absorb.wgsl `absorb_share`; its length in a liquid bridge, bridges.wgsl
// `hair_length`).
fn rest_around(i: u32) -> f32 {
    let pt = points[i];
    var before = 0.0;
    if (i > pt.first) {
        before = points[i - 1u].rest_stretch;
    }
    var after = 0.0;
    if (i < pt.last) {
        after = pt.rest_stretch;
    }
    return before + after;
}
