//! Hair-hair volume on the CPU (`physics/volume.rs`, pass `volume`): once a step, each worker
//! spreads its blocks' free points onto a grid of its own, the grids are summed (exactly: the
//! sums are integers, so any thread count gives the same grid), and each worker moves its
//! points' velocities by what they see. Nothing here exists without hair-hair volume.

use super::layout::StateRow;
use super::pool::Pool;
use crate::error::Result;
use crate::groom::Groom;
use crate::physics::lanes::{Lane, ParamRow, W};
use crate::physics::volume::{respond, rest_density_of, sample, spread, spread_mass, CellSums, VolumeGrid, VolumeLaw};
use glam::Affine3A;
use rayon::prelude::*;

/// The grid, the rest density, and one grid of sums per worker.
#[derive(Debug)]
pub(super) struct Volume {
    grid: VolumeGrid,
    rest: f32,
    params: crate::params::Volume,
    /// One per worker; the first holds the total after the sum.
    sums: Vec<Vec<CellSums>>,
}

impl Volume {
    /// The grid over `groom`'s reach, its rest density (measured unless given), and `workers`
    /// grids of sums.
    pub(super) fn new(groom: &Groom, p: &crate::params::Volume, workers: usize) -> Result<Volume> {
        let grid = VolumeGrid::for_groom(groom, p.cell)?;
        let rest = rest_density_of(p, &grid, groom);
        Ok(Volume {
            grid,
            rest,
            params: *p,
            sums: vec![vec![CellSums::default(); grid.cells()]; workers.max(1)],
        })
    }

    /// Pass volume over `state` (`chunk_rows` rows per worker) for a step of `dt` starting
    /// under `head`; `params` gives each row's inverse masses (0: pinned, left alone), `wet`
    /// each row's wetness (empty: dry).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn run(
        &mut self,
        state: &mut [StateRow],
        params: &[ParamRow],
        wet: &[Lane],
        chunk_rows: usize,
        head: &Affine3A,
        dt: f32,
        pool: Option<&Pool>,
    ) {
        let (grid, rest) = (self.grid, self.rest);
        let to_head = head.inverse();
        let law = VolumeLaw::new(&self.params, self.rest, dt, glam::Mat3::from(head.matrix3));
        let sums = &mut self.sums;
        let mut body = || {
            // Spread: each worker its chunk onto its own grid (a worker without a chunk
            // leaves its grid empty).
            let all: &[StateRow] = state;
            sums.par_iter_mut().enumerate().for_each(|(k, g)| {
                g.fill(CellSums::default());
                let (lo, hi) = ((k * chunk_rows).min(all.len()), ((k + 1) * chunk_rows).min(all.len()));
                for (i, (r, p)) in all[lo..hi].iter().zip(&params[lo..hi]).enumerate() {
                    let w = wet.get(lo + i).copied().unwrap_or([0.0; W]);
                    for l in 0..W {
                        if p.inv_mass[l] > 0.0 {
                            let x = to_head.transform_point3(r.x.get(l));
                            spread(&grid, g, x, r.v.get(l), spread_mass(1.0 / p.inv_mass[l], w[l]));
                        }
                    }
                }
            });
            // Sum into the first grid, a range of cells per task.
            let (total, others) = sums.split_first_mut().expect("one grid at least");
            let span = total.len().div_ceil(4 * others.len().max(1)).max(1024);
            total.par_chunks_mut(span).enumerate().for_each(|(k, t)| {
                for other in others.iter() {
                    for (a, b) in t.iter_mut().zip(&other[k * span..]) {
                        a.add(b);
                    }
                }
            });
            // Respond: each worker its chunk, from the total.
            let total = &sums[0];
            state
                .par_chunks_mut(chunk_rows)
                .zip(params.par_chunks(chunk_rows))
                .enumerate()
                .for_each(|(k, (rows, prm))| {
                    for (i, (r, p)) in rows.iter_mut().zip(prm).enumerate() {
                        let w = wet.get(k * chunk_rows + i).copied().unwrap_or([0.0; W]);
                        for l in 0..W {
                            if p.inv_mass[l] <= 0.0 {
                                continue;
                            }
                            let x = to_head.transform_point3(r.x.get(l));
                            if let Some(s) = sample(&grid, total, x, rest) {
                                r.v.set(l, respond(r.v.get(l), &s, &law, w[l]));
                            }
                        }
                    }
                });
        };
        match pool {
            Some(p) => p.install(body),
            None => body(),
        }
    }
}
