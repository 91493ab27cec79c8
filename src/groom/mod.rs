//! Strand storage: the host's rest-pose strands, however they were made.
//!
//! A [`Groom`] is what every source produces: the procedural paper scene, the `.tfx` and
//! `.hair` loaders, and the C API's `wethair_groom_create` from the host's own arrays. The
//! simulation copies what it needs at create, so a groom can be dropped or reused afterwards.

mod cyhair;
mod options;
mod paper;
mod tfx;
mod usc;

pub use cyhair::load_cyhair;
pub use options::{LoadOptions, LoadReport, UpAxis};
pub use paper::{paper_scene, PaperScene};
pub use tfx::load_tfx;
pub use usc::load_usc;

use crate::error::{invalid, Error, Result};
use glam::Vec3;

/// Most points one strand may have; fixed so that per-strand scratch needs no allocation.
pub const MAX_POINTS_PER_STRAND: usize = 256;
/// Most strands one groom may have.
pub const MAX_STRANDS: usize = 1 << 22;
/// Most points one groom may have (all strands together).
pub const MAX_POINTS: usize = 1 << 26;

/// Rest-pose strands in the head's local space (SI units recommended: metres, kilograms).
#[derive(Debug, Clone, PartialEq)]
pub struct Groom {
    /// Every point's rest position, strand after strand, root first.
    pub(crate) positions: Vec<Vec3>,
    /// Offsets into `positions`: strand `s` is `strand_first[s]..strand_first[s + 1]`.
    pub(crate) strand_first: Vec<u32>,
    /// Per point: pinned points follow the head transform rigidly (inverse mass 0).
    pub(crate) pinned: Vec<bool>,
    /// Per point mass in kg (ignored for pinned points).
    pub(crate) mass: Vec<f32>,
    /// What the loader welded or dropped (empty for grooms not read from a file).
    pub(crate) load_report: LoadReport,
}

impl Groom {
    /// Builds a groom from the host's arrays and validates it.
    ///
    /// `strand_points[s]` is the number of points of strand `s` (>= 2). `pinned` marks points
    /// that follow the head; `None` pins each strand's root. `mass` is per point; `None` uses
    /// `default_mass` for every point.
    pub fn new(
        positions: Vec<Vec3>,
        strand_points: &[u32],
        pinned: Option<Vec<bool>>,
        mass: Option<Vec<f32>>,
        default_mass: f32,
    ) -> Result<Self> {
        if strand_points.is_empty() {
            return Err(invalid!("a groom needs at least one strand"));
        }
        if strand_points.len() > MAX_STRANDS {
            return Err(Error::Capacity(format!(
                "{} strands, at most {MAX_STRANDS}",
                strand_points.len()
            )));
        }
        let mut strand_first = Vec::with_capacity(strand_points.len() + 1);
        let mut total: usize = 0;
        strand_first.push(0u32);
        for (s, &n) in strand_points.iter().enumerate() {
            if n < 2 || n as usize > MAX_POINTS_PER_STRAND {
                return Err(invalid!(
                    "strand {s} has {n} points; each strand needs 2..={MAX_POINTS_PER_STRAND}"
                ));
            }
            total += n as usize;
            if total > MAX_POINTS {
                return Err(Error::Capacity(format!("more than {MAX_POINTS} points")));
            }
            strand_first.push(total as u32);
        }
        if positions.len() != total {
            return Err(invalid!(
                "{} positions given, the strand point counts add up to {total}",
                positions.len()
            ));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(invalid!("position {i} is not finite: {:?}", positions[i]));
        }
        let pinned = match pinned {
            Some(p) if p.len() != total => return Err(invalid!("{} pinned flags for {total} points", p.len())),
            Some(p) => p,
            None => {
                let mut p = vec![false; total];
                for &f in &strand_first[..strand_first.len() - 1] {
                    p[f as usize] = true;
                }
                p
            }
        };
        let mass = match mass {
            Some(m) if m.len() != total => return Err(invalid!("{} masses for {total} points", m.len())),
            Some(m) => m,
            None => vec![default_mass; total],
        };
        for (i, (&m, &pin)) in mass.iter().zip(&pinned).enumerate() {
            if !(pin || m.is_finite() && m > 0.0) {
                return Err(invalid!("point {i} has mass {m}; free points need finite mass > 0"));
            }
        }
        Ok(Groom {
            positions,
            strand_first,
            pinned,
            mass,
            load_report: LoadReport::default(),
        })
    }

    /// What loading welded or dropped ([`LoadOptions::weld_length`]); its
    /// [`LoadReport::message`] is "" when nothing was.
    pub fn load_report(&self) -> &LoadReport {
        &self.load_report
    }

    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.strand_first.len() - 1
    }

    /// Number of points over all strands.
    pub fn point_count(&self) -> usize {
        self.positions.len()
    }

    /// The point range of strand `s`.
    pub fn strand_range(&self, s: usize) -> std::ops::Range<usize> {
        self.strand_first[s] as usize..self.strand_first[s + 1] as usize
    }

    /// Rest positions, strand after strand.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Per-point pinned flags.
    pub fn pinned(&self) -> &[bool] {
        &self.pinned
    }

    /// Per-point masses in kg.
    pub fn masses(&self) -> &[f32] {
        &self.mass
    }

    /// The most points any strand has.
    pub fn max_strand_points(&self) -> usize {
        self.strand_first
            .windows(2)
            .map(|w| (w[1] - w[0]) as usize)
            .max()
            .unwrap_or(0)
    }

    /// Axis-aligned bounds of the rest pose.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        crate::physics::morton::bounds(&self.positions)
    }

    /// Each strand's root (first point), in strand order.
    pub fn roots(&self) -> Vec<Vec3> {
        self.strand_first[..self.strand_count()]
            .iter()
            .map(|&f| self.positions[f as usize])
            .collect()
    }

    /// The strands `which` (in that order) as a groom of their own.
    pub fn subset(&self, which: &[u32]) -> Groom {
        let mut g = Groom {
            positions: Vec::new(),
            strand_first: vec![0],
            pinned: Vec::new(),
            mass: Vec::new(),
            load_report: LoadReport::default(),
        };
        for &s in which {
            let r = self.strand_range(s as usize);
            g.positions.extend_from_slice(&self.positions[r.clone()]);
            g.pinned.extend_from_slice(&self.pinned[r.clone()]);
            g.mass.extend_from_slice(&self.mass[r]);
            g.strand_first.push(g.positions.len() as u32);
        }
        g
    }

    /// The longest strand's rest length (sum of its segment lengths).
    pub fn max_strand_length(&self) -> f32 {
        (0..self.strand_count())
            .map(|s| {
                let r = self.strand_range(s);
                self.positions[r]
                    .windows(2)
                    .map(|w| (w[1] - w[0]).length())
                    .sum::<f32>()
            })
            .fold(0.0, f32::max)
    }

    /// Sets every point's mass (kg); pinned points keep theirs, which is unused.
    pub fn set_uniform_mass(&mut self, mass: f32) {
        self.mass.iter_mut().for_each(|m| *m = mass);
    }
}

/// Reads a little-endian `u32` at `off`, or a parse error naming `what` when out of bounds.
pub(crate) fn read_u32(bytes: &[u8], off: usize, what: &str) -> Result<u32> {
    bytes
        .get(off..off.checked_add(4).ok_or_else(|| truncated(what))?)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .ok_or_else(|| truncated(what))
}

/// Reads a little-endian `f32` at `off`, or a parse error naming `what` when out of bounds.
pub(crate) fn read_f32(bytes: &[u8], off: usize, what: &str) -> Result<f32> {
    read_u32(bytes, off, what).map(f32::from_bits)
}

/// The error for a file that ends before `what`.
pub(crate) fn truncated(what: &str) -> Error {
    Error::Parse(format!("file ends before {what}"))
}

/// Loads a groom from a file, choosing the format by its content (`HAIR` signature) or
/// extension (`.tfx`, `.data`). Units are the file's own; `mass` is given to every point.
pub fn load_file(path: &std::path::Path, mass: f32) -> Result<Groom> {
    load_file_with(path, &LoadOptions::with_point_mass(mass))
}

/// Loads a groom from a file (as [`load_file`]) and applies `options`: scale, up axis,
/// masses, subsampling and resampling.
pub fn load_file_with(path: &std::path::Path, options: &LoadOptions) -> Result<Groom> {
    options.validate()?;
    let bytes = std::fs::read(path).map_err(|e| Error::Io(format!("{}: {e}", path.display())))?;
    let has_ext = |x: &str| path.extension().is_some_and(|e| e.eq_ignore_ascii_case(x));
    let m = options.point_mass;
    let file = if bytes.starts_with(b"HAIR") {
        load_cyhair(&bytes, m)
    } else if has_ext("tfx") {
        load_tfx(&bytes, m)
    } else if has_ext("data") {
        load_usc(&bytes, m)
    } else {
        Err(Error::Parse(format!(
            "{}: not a Cem Yuksel .hair file (no HAIR signature), a TressFX .tfx file nor a \
             USC-HairSalon .data file",
            path.display()
        )))
    }?;
    if *options == LoadOptions::with_point_mass(m) {
        return Ok(file);
    }
    options.apply(&file)
}
