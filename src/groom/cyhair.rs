//! Cem Yuksel's `.hair` format loader.
//!
//! A 128-byte header: `"HAIR"`, u32 strand count, u32 point count, u32 array flags (bit 0
//! segments, 1 points, 2 thickness, 3 transparency, 4 colours), u32 default segments, f32
//! default thickness, f32 default transparency, f32×3 default colour, 88 bytes of text. Then
//! the arrays in that order: u16 segments per strand, f32×3 points, f32 thickness, f32
//! transparency, f32×3 colours. A strand of `n` segments has `n + 1` points; the root (first
//! point) is pinned.

use super::{read_u32, Groom, MAX_POINTS, MAX_POINTS_PER_STRAND};
use crate::error::{Error, Result};
use glam::Vec3;

const HEADER_BYTES: usize = 128;
const HAS_SEGMENTS: u32 = 1 << 0;
const HAS_POINTS: u32 = 1 << 1;

/// Parses a `.hair` file's bytes; every point gets `mass` kg.
pub fn load_cyhair(bytes: &[u8], mass: f32) -> Result<Groom> {
    if bytes.len() < HEADER_BYTES || &bytes[..4] != b"HAIR" {
        return Err(Error::Parse(
            "not a .hair file: no HAIR signature or short header".into(),
        ));
    }
    let strands = read_u32(bytes, 4, "strand count")? as usize;
    let points = read_u32(bytes, 8, "point count")? as usize;
    let flags = read_u32(bytes, 12, "array flags")?;
    let default_segments = read_u32(bytes, 16, "default segment count")? as usize;
    if flags & HAS_POINTS == 0 {
        return Err(Error::Parse(".hair file has no point array".into()));
    }
    if strands == 0 || points > MAX_POINTS || strands > points {
        return Err(Error::Parse(format!(
            ".hair header: {strands} strands, {points} points"
        )));
    }
    let mut off = HEADER_BYTES;
    let counts: Vec<u32> = if flags & HAS_SEGMENTS != 0 {
        let end = off + strands * 2;
        let seg = bytes.get(off..end).ok_or_else(|| super::truncated("segment array"))?;
        off = end;
        seg.chunks_exact(2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]) as u32 + 1)
            .collect()
    } else {
        vec![default_segments.saturating_add(1).min(u32::MAX as usize) as u32; strands]
    };
    if let Some(s) = counts.iter().position(|&n| n < 2 || n as usize > MAX_POINTS_PER_STRAND) {
        return Err(Error::Parse(format!(
            "strand {s} has {} points; wethair takes 2..={MAX_POINTS_PER_STRAND}",
            counts[s]
        )));
    }
    let sum: usize = counts.iter().map(|&n| n as usize).sum();
    if sum != points {
        return Err(Error::Parse(format!(
            "segment counts add up to {sum} points, header says {points}"
        )));
    }
    let end = off + points * 12;
    let data = bytes.get(off..end).ok_or_else(|| super::truncated("point array"))?;
    let mut positions = Vec::with_capacity(points);
    for (i, v) in data.chunks_exact(12).enumerate() {
        let f = |k: usize| f32::from_le_bytes([v[4 * k], v[4 * k + 1], v[4 * k + 2], v[4 * k + 3]]);
        let p = Vec3::new(f(0), f(1), f(2));
        if !p.is_finite() {
            return Err(Error::Parse(format!(".hair point {i} is not finite")));
        }
        positions.push(p);
    }
    Groom::new(positions, &counts, None, None, mass).map_err(|e| Error::Parse(format!(".hair: {e}")))
}
