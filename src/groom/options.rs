//! What a loader does to a file's strands before they become a groom: units to metres, the
//! up axis, point masses, strand subsampling and resampling. Every loader goes through it, so
//! `.tfx`, `.hair` and `.data` files get the same options.

use super::Groom;
use crate::error::{check_non_negative, check_positive, invalid, Result};
use glam::Vec3;

/// Which way is up in a groom file (`WetHairLoadDesc::up_axis`); exported as
/// `WetHairUpAxis`.
/// cbindgen:rename-all=prefix:WETHAIR_UP_AXIS_
#[repr(u32)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum UpAxis {
    /// Keep the file's axes (the file is z up like the simulation's defaults, or the host
    /// works in the file's own convention and sets gravity to match).
    #[default]
    KEEP = 0,
    /// The file is y up: turn it a quarter turn about x so that its y becomes z
    /// (`(x, y, z)` to `(x, -z, y)`, a rotation: handedness is kept).
    Y_TO_Z = 1,
}

/// How a groom file is read into simulation units. [`LoadOptions::default`] keeps the file's
/// units and axes, gives the strands 1 g per metre and welds segments shorter than 0.1 mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadOptions {
    /// Metres per file unit (0.01 for a file in centimetres), > 0.
    pub scale: f32,
    /// Which way is up in the file.
    pub up_axis: UpAxis,
    /// Mass of every point, kg, > 0 (used when `linear_density` is 0).
    pub point_mass: f32,
    /// Mass per metre of strand, kg/m, >= 0; when > 0 each point gets the mass of half of its
    /// two segments (human hair is about 6e-5 kg/m: 1.3 g/cm³ at 80 µm).
    pub linear_density: f32,
    /// Keep every Nth strand (1 = all), >= 1: a lighter groom from a dense file.
    pub strand_stride: u32,
    /// Resample each strand to this many points evenly spaced along its length (0 = keep the
    /// file's points; otherwise 2..=256).
    pub resample_points: u32,
    /// Segments shorter than this (m, after `scale`) are welded: the later point is dropped
    /// (the tip moves onto the point before it), and a strand shorter than this is dropped.
    /// 0 keeps every point. Files carry such segments by accident (sub-micrometre ones are
    /// common); kept, each becomes a spring stiffer than the rest of the groom together.
    pub weld_length: f32,
}

/// What loading did to a file's strands: [`Groom::load_report`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LoadReport {
    /// Points removed by welding (those of dropped strands included).
    pub welded_points: u32,
    /// Strands dropped because they were shorter than the weld length.
    pub dropped_strands: u32,
    /// The weld length used, m.
    pub weld_length: f32,
}

impl LoadReport {
    /// A one-line account, or "" when nothing was welded.
    pub fn message(&self) -> String {
        if self.welded_points == 0 && self.dropped_strands == 0 {
            return String::new();
        }
        format!(
            "welded {} points of segments shorter than {} m; dropped {} strands shorter than that              (later strands move up)",
            self.welded_points, self.weld_length, self.dropped_strands
        )
    }
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            scale: 1.0,
            up_axis: UpAxis::KEEP,
            point_mass: 1.0e-3,
            linear_density: 1.0e-3,
            strand_stride: 1,
            resample_points: 0,
            weld_length: 1.0e-4,
        }
    }
}

impl LoadOptions {
    /// Options that only set every point's mass and keep every point of the file (the
    /// loaders' old behaviour, for files whose units are unknown).
    pub fn with_point_mass(point_mass: f32) -> Self {
        LoadOptions {
            point_mass,
            linear_density: 0.0,
            weld_length: 0.0,
            ..Default::default()
        }
    }

    /// Checks every field; the error names the first bad one and its range.
    pub fn validate(&self) -> Result<()> {
        check_positive("load scale", self.scale)?;
        check_positive("load point_mass", self.point_mass)?;
        check_non_negative("load linear_density", self.linear_density)?;
        check_non_negative("load weld_length", self.weld_length)?;
        if self.strand_stride == 0 {
            return Err(invalid!("load strand_stride must be >= 1, got 0"));
        }
        let n = self.resample_points;
        if n != 0 && !(2..=super::MAX_POINTS_PER_STRAND as u32).contains(&n) {
            return Err(invalid!(
                "load resample_points must be 0 or 2..={}, got {n}",
                super::MAX_POINTS_PER_STRAND
            ));
        }
        Ok(())
    }

    /// Applies the options to a groom as a loader read it (file units, file axes).
    pub fn apply(&self, file: &Groom) -> Result<Groom> {
        self.validate()?;
        let counts: Vec<u32> = file.strand_first.windows(2).map(|w| w[1] - w[0]).collect();
        let (positions, pinned) = (&file.positions, &file.pinned);
        let turn = |p: Vec3| match self.up_axis {
            UpAxis::KEEP => p,
            UpAxis::Y_TO_Z => Vec3::new(p.x, -p.z, p.y),
        };
        let (mut pos, mut pin, mut out_counts) = (Vec::new(), Vec::new(), Vec::new());
        let mut report = LoadReport {
            weld_length: self.weld_length,
            ..Default::default()
        };
        let mut first = 0usize;
        for (s, &n) in counts.iter().enumerate() {
            let r = first..first + n as usize;
            first = r.end;
            if s % self.strand_stride as usize != 0 {
                continue;
            }
            let pts: Vec<Vec3> = positions[r.clone()].iter().map(|&p| turn(p) * self.scale).collect();
            let (pts, fixed) = weld(&pts, &pinned[r], self.weld_length);
            report.welded_points += n - pts.len() as u32;
            if pts.len() < 2 {
                // The strand's last point goes with it: every file point is kept or counted.
                report.welded_points += pts.len() as u32;
                report.dropped_strands += 1;
                continue;
            }
            if self.resample_points == 0 {
                out_counts.push(pts.len() as u32);
                pos.extend(pts);
                pin.extend(fixed);
            } else {
                let (p, f) = resample(&pts, &fixed, self.resample_points as usize);
                pos.extend(p);
                pin.extend(f);
                out_counts.push(self.resample_points);
            }
        }
        if out_counts.is_empty() {
            return Err(invalid!(
                "every strand is shorter than load weld_length ({} m); check the scale",
                self.weld_length
            ));
        }
        let masses = (self.linear_density > 0.0).then(|| point_masses(&pos, &out_counts, self.linear_density));
        let mut g = Groom::new(pos, &out_counts, Some(pin), masses, self.point_mass)?;
        g.load_report = report;
        Ok(g)
    }
}

/// Drops every point closer than `min` to the last point kept (the root is always kept); a
/// tip that would be dropped replaces the free point before it, so the strand keeps its
/// length. Fewer than two points left means the strand is shorter than `min`.
fn weld(pts: &[Vec3], fixed: &[bool], min: f32) -> (Vec<Vec3>, Vec<bool>) {
    if min <= 0.0 {
        return (pts.to_vec(), fixed.to_vec());
    }
    let (mut p, mut f) = (vec![pts[0]], vec![fixed[0]]);
    for i in 1..pts.len() {
        let last = *p.last().unwrap_or(&pts[0]);
        if (pts[i] - last).length() >= min {
            p.push(pts[i]);
            f.push(fixed[i]);
        } else if i + 1 == pts.len() && p.len() >= 2 && !f[p.len() - 1] {
            // The tip is within `min` of a free point: the tip takes its place.
            let n = p.len();
            p[n - 1] = pts[i];
            f[n - 1] = fixed[i];
            if (p[n - 1] - p[n - 2]).length() < min {
                p.pop();
                f.pop();
            }
        }
    }
    (p, f)
}

/// `n` points evenly spaced along the polyline `pts` by arc length (ends kept). A new point is
/// pinned when it lies within the strand's pinned prefix (the root always is).
fn resample(pts: &[Vec3], fixed: &[bool], n: usize) -> (Vec<Vec3>, Vec<bool>) {
    let mut arc = Vec::with_capacity(pts.len());
    let mut total = 0.0f64;
    arc.push(0.0);
    for w in pts.windows(2) {
        total += (w[1] - w[0]).length() as f64;
        arc.push(total);
    }
    let pinned_prefix = fixed.iter().take_while(|&&f| f).count();
    let pinned_arc = if pinned_prefix == 0 {
        0.0
    } else {
        arc[pinned_prefix - 1]
    };
    let mut out = Vec::with_capacity(n);
    let mut pin = Vec::with_capacity(n);
    let mut seg = 0usize;
    for k in 0..n {
        let t = total * k as f64 / (n - 1) as f64;
        while seg + 2 < arc.len() && arc[seg + 1] < t {
            seg += 1;
        }
        let len = arc[seg + 1] - arc[seg];
        let u = if len > 0.0 {
            ((t - arc[seg]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(pts[seg].lerp(pts[seg + 1], u as f32));
        pin.push(k == 0 || t <= pinned_arc * (1.0 + 1e-9));
    }
    (out, pin)
}

/// Each point's mass from a linear density: half of each segment it touches.
fn point_masses(pos: &[Vec3], counts: &[u32], density: f32) -> Vec<f32> {
    let mut m = vec![0.0f32; pos.len()];
    let mut first = 0usize;
    for &n in counts {
        let r = first..first + n as usize;
        for i in r.start..r.end - 1 {
            let half = 0.5 * density * (pos[i + 1] - pos[i]).length();
            m[i] += half;
            m[i + 1] += half;
        }
        first = r.end;
    }
    // A point whose segments are all degenerate gets a floor, not a zero mass.
    let floor = m.iter().copied().filter(|&x| x > 0.0).fold(f32::INFINITY, f32::min);
    let floor = if floor.is_finite() { floor } else { density * 1e-3 };
    m.iter_mut().filter(|x| **x <= 0.0).for_each(|x| *x = floor);
    m
}
