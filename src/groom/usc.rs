//! USC-HairSalon `.data` loader (the format of the USC HairSalon and Digital Salon groom
//! collections).
//!
//! Layout (little endian): i32 strand count, then per strand an i32 point count and that many
//! float3 positions, root first. The collections hold strands of 0 or 1 point (roots where
//! the artist grew no hair); they cannot be simulated and are skipped. The files are y up in
//! their own units ([`super::LoadOptions`] turns and scales them). Every count is checked
//! against the file before it is read.

use super::{read_u32, Groom, MAX_POINTS, MAX_POINTS_PER_STRAND, MAX_STRANDS};
use crate::error::{Error, Result};
use glam::Vec3;

/// Parses a `.data` file's bytes; every point gets `mass` kg, each strand's root is pinned.
pub fn load_usc(bytes: &[u8], mass: f32) -> Result<Groom> {
    let strands = read_u32(bytes, 0, "strand count")? as i32;
    if strands <= 0 || strands as usize > MAX_STRANDS {
        return Err(Error::Parse(format!(
            ".data strand count {strands}: wethair takes 1..={MAX_STRANDS}"
        )));
    }
    let (mut positions, mut counts) = (Vec::new(), Vec::new());
    let mut off = 4usize;
    for s in 0..strands as usize {
        let n = read_u32(bytes, off, "a strand's point count")? as i32;
        off += 4;
        if !(0..=MAX_POINTS_PER_STRAND as i32).contains(&n) {
            return Err(Error::Parse(format!(
                ".data strand {s} has {n} points; wethair takes 0..={MAX_POINTS_PER_STRAND}"
            )));
        }
        let n = n as usize;
        let data = bytes
            .get(off..off + 12 * n)
            .ok_or_else(|| Error::Parse(format!(".data file ends inside strand {s} ({n} points)")))?;
        off += 12 * n;
        if n < 2 {
            continue;
        }
        if positions.len() + n > MAX_POINTS {
            return Err(Error::Capacity(format!(
                ".data file holds more than {MAX_POINTS} points"
            )));
        }
        for (i, v) in data.chunks_exact(12).enumerate() {
            let f = |k: usize| f32::from_le_bytes([v[4 * k], v[4 * k + 1], v[4 * k + 2], v[4 * k + 3]]);
            let p = Vec3::new(f(0), f(1), f(2));
            if !p.is_finite() {
                return Err(Error::Parse(format!(".data strand {s} point {i} is not finite")));
            }
            positions.push(p);
        }
        counts.push(n as u32);
    }
    if off != bytes.len() {
        return Err(Error::Parse(format!(
            ".data file has {} bytes after its {strands} strands",
            bytes.len() - off
        )));
    }
    if counts.is_empty() {
        return Err(Error::Parse(".data file has no strand of 2 or more points".into()));
    }
    Groom::new(positions, &counts, None, None, mass).map_err(|e| Error::Parse(format!(".data: {e}")))
}
