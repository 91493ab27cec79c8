//! The springs' rest lengths, taken from the groom's rest pose once: the CPU layout, the GPU's
//! point records, the energy diagnostic and the f64 reference all read these numbers.

use crate::groom::Groom;

/// Per point, in the host's order: the rest length to the next point (stretch) and to the
/// point after next (bend), 0 where the strand has no such point. Computed in f32 from the f32
/// rest pose, so every consumer starts from the same bits.
pub fn rest_lengths(g: &Groom) -> Vec<[f32; 2]> {
    let pos = g.positions();
    let mut rest = vec![[0.0; 2]; pos.len()];
    for s in 0..g.strand_count() {
        let r = g.strand_range(s);
        for i in r.clone() {
            if i + 1 < r.end {
                rest[i][0] = (pos[i + 1] - pos[i]).length();
            }
            if i + 2 < r.end {
                rest[i][1] = (pos[i + 2] - pos[i]).length();
            }
        }
    }
    rest
}
