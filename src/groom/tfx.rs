//! TressFX `.tfx` loader: the 3.x and 4.x layouts (little endian).
//!
//! Both start with an f32 `version`, a u32 strand count and a u32 vertex count per strand.
//!
//! - **4.x**: then u32 byte offsets to the vertex positions, strand UVs, vertex UVs, strand
//!   thickness and vertex colours (0 = absent), and 32 reserved u32 (a 160-byte header).
//!   Positions are float4 per vertex; `w == 0` marks a vertex fixed to the head.
//! - **3.x**: the u32 at byte 144 is the byte offset of the positions, float3 per vertex
//!   (12 bytes), strand after strand, root first; nothing marks fixed vertices, so each
//!   strand's root is pinned. The other header words are not read.
//!
//! Other versions are refused, naming the version found. Every offset and size is checked
//! against the file before it is read. Units are the file's own ([`super::LoadOptions`]
//! scales and turns them).

use super::{read_f32, read_u32, Groom, MAX_POINTS, MAX_POINTS_PER_STRAND};
use crate::error::{Error, Result};
use glam::Vec3;

const HEADER_BYTES: usize = 4 * 8 + 32 * 4;
/// Where a 3.x header keeps the byte offset of its positions.
const V3_POSITION_OFFSET_AT: usize = 144;

/// Parses a `.tfx` file's bytes; every point gets `mass` kg.
pub fn load_tfx(bytes: &[u8], mass: f32) -> Result<Groom> {
    if bytes.len() < HEADER_BYTES {
        return Err(Error::Parse(format!(
            "tfx header needs {HEADER_BYTES} bytes, file has {}",
            bytes.len()
        )));
    }
    let version = read_f32(bytes, 0, "version")?;
    let v3 = (3.0..4.0).contains(&version);
    if !(v3 || (4.0..5.0).contains(&version)) {
        return Err(Error::Parse(format!(
            "tfx version {version}: wethair reads TressFX 3.x and 4.x files"
        )));
    }
    let strands = read_u32(bytes, 4, "strand count")? as usize;
    let per_strand = read_u32(bytes, 8, "vertices per strand")? as usize;
    let offset_at = if v3 { V3_POSITION_OFFSET_AT } else { 12 };
    let offset = read_u32(bytes, offset_at, "position offset")? as usize;
    let stride = if v3 { 12 } else { 16 };
    if strands == 0 {
        return Err(Error::Parse("tfx has 0 strands".into()));
    }
    if !(2..=MAX_POINTS_PER_STRAND).contains(&per_strand) {
        return Err(Error::Parse(format!(
            "tfx has {per_strand} vertices per strand; wethair takes 2..={MAX_POINTS_PER_STRAND}"
        )));
    }
    let total = strands
        .checked_mul(per_strand)
        .filter(|&t| t <= MAX_POINTS)
        .ok_or_else(|| Error::Capacity(format!("{strands} x {per_strand} points")))?;
    if offset < HEADER_BYTES {
        return Err(Error::Parse(format!(
            "tfx position offset {offset} points into the header"
        )));
    }
    let end = offset
        .checked_add(total * stride)
        .filter(|&e| e <= bytes.len())
        .ok_or_else(|| {
            Error::Parse(format!(
                "tfx {version} positions ({total} x {stride} bytes at offset {offset}) run past the end ({} bytes)",
                bytes.len()
            ))
        })?;
    // The optional arrays are not used, but a file that cannot hold them is truncated.
    let optional = [
        (16, "strand UVs", strands * 8),
        (20, "vertex UVs", total * 8),
        (24, "strand thickness", strands * 4),
        (28, "vertex colours", total * 16),
    ];
    for (at, what, size) in optional.into_iter().filter(|_| !v3) {
        let off = read_u32(bytes, at, what)? as usize;
        if off != 0 && (off < HEADER_BYTES || off + size > bytes.len()) {
            return Err(Error::Parse(format!(
                "tfx {what} ({size} bytes at offset {off}) do not fit in the file ({} bytes)",
                bytes.len()
            )));
        }
    }
    let data = &bytes[offset..end];
    let mut positions = Vec::with_capacity(total);
    let mut pinned = Vec::with_capacity(total);
    for (i, v) in data.chunks_exact(stride).enumerate() {
        let f = |k: usize| f32::from_le_bytes([v[4 * k], v[4 * k + 1], v[4 * k + 2], v[4 * k + 3]]);
        let p = Vec3::new(f(0), f(1), f(2));
        if !p.is_finite() {
            return Err(Error::Parse(format!("tfx vertex {i} is not finite")));
        }
        positions.push(p);
        // 3.x marks nothing: only the roots are pinned, below.
        pinned.push(!v3 && f(3) == 0.0);
    }
    // A strand with no fixed vertex would fall away from the head: pin its root.
    for s in 0..strands {
        let r = s * per_strand..(s + 1) * per_strand;
        if !pinned[r.clone()].iter().any(|&p| p) {
            pinned[r.start] = true;
        }
    }
    Groom::new(positions, &vec![per_strand as u32; strands], Some(pinned), None, mass)
        .map_err(|e| Error::Parse(format!("tfx: {e}")))
}
