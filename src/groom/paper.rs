//! The paper scene as `docs/METHOD.md` §6 defines it (the scene wethair is compared with other
//! engines on): roots on the upper hemisphere of a 0.1 m head by a Fibonacci
//! spiral, strands straight along the normal, 0.02 m segments, 1 g per point, roots pinned.

use super::Groom;
use crate::error::{invalid, Result};
use glam::{DVec3, Vec3};

/// The paper scene's geometric constants (SI units).
pub struct PaperScene;

impl PaperScene {
    /// Head sphere radius, m.
    pub const HEAD_RADIUS: f32 = 0.1;
    /// Segment rest length, m.
    pub const SEGMENT: f32 = 0.02;
    /// Mass of every point, kg.
    pub const POINT_MASS: f32 = 1.0e-3;
    /// Strand count of the paper's figures.
    pub const STRANDS: u32 = 10_000;
    /// Points per strand in the paper's figures.
    pub const POINTS: u32 = 6;
}

/// Builds the paper scene with `strands` strands of `points` points each.
pub fn paper_scene(strands: u32, points: u32) -> Result<Groom> {
    if strands == 0 || points < 2 {
        return Err(invalid!(
            "paper scene needs >= 1 strand and >= 2 points, got {strands} x {points}"
        ));
    }
    let n = strands as usize;
    let p = points as usize;
    let mut positions = Vec::with_capacity(n.saturating_mul(p).min(super::MAX_POINTS));
    for i in 0..n {
        // Computed in f64 like scene.py, then rounded once, so positions match it bit for bit.
        let z = 1.0 - (i as f64 + 0.5) / n as f64;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = i as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let normal = DVec3::new(r * phi.cos(), r * phi.sin(), z);
        for j in 0..p {
            let off = 0.1f64 + 0.02f64 * j as f64; // R_HEAD + SEG * j, in f64 as scene.py
            let q = normal * off;
            positions.push(Vec3::new(q.x as f32, q.y as f32, q.z as f32));
        }
        if positions.len() > super::MAX_POINTS {
            break; // Groom::new reports the capacity error
        }
    }
    let counts = vec![points; n];
    Groom::new(positions, &counts, None, None, PaperScene::POINT_MASS)
}
