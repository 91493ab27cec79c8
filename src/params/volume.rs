//! Hair-hair volume's parameters (docs/VOLUME.md): off unless asked for, and then a grid, a
//! pass and its buffers exist only in that scene.

use crate::error::{check_non_negative, check_positive, invalid, Result};

/// Hair-hair volume (docs/VOLUME.md): once a step the hair's mass and momentum are spread
/// over a grid that follows the head; where the hair is denser than it was at rest a pressure
/// pushes points down the density gradient (the groom keeps its volume), and every point's
/// velocity relaxes toward the grid's (hair-hair friction: strands that touch move together).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Volume {
    /// Whether the grid runs (off: no grid, no pass).
    pub enabled: bool,
    /// The grid's cell, m (head space).
    pub cell: f32,
    /// Pressure stiffness, m²/s²: a point where the density exceeds the rest density
    /// accelerates by `pressure · ∇ρ / ρ_rest` down the gradient. It acts once a step, so it is
    /// stable while its sound speed crosses less than a cell a step, `√pressure · dt < cell`
    /// (at 60 Hz and 2 cm cells, pressure below 1.44); the default 1 keeps inside that.
    pub pressure: f32,
    /// Hair-hair friction, 1/s: each step a point's velocity moves `1 - exp(-friction dt)` of
    /// the way to the grid's velocity at it.
    pub friction: f32,
    /// The density above which the pressure acts, kg/m³; 0 (the default) measures it from the
    /// rest pose (the mass-weighted mean density the hair points see at rest).
    pub rest_density: f32,
}

impl Volume {
    /// Off: no grid, no pass.
    pub const OFF: Volume = Volume {
        enabled: false,
        cell: 0.02,
        pressure: 1.0,
        friction: 4.0,
        rest_density: 0.0,
    };

    /// On with the documented defaults.
    pub const ON: Volume = Volume {
        enabled: true,
        ..Volume::OFF
    };

    /// Checks every field by name.
    pub fn validate(&self) -> Result<()> {
        check_positive("volume.cell", self.cell)?;
        check_non_negative("volume.pressure", self.pressure)?;
        check_non_negative("volume.friction", self.friction)?;
        check_non_negative("volume.rest_density", self.rest_density)?;
        if self.cell > 1.0 {
            return Err(invalid!("volume.cell must be at most 1 m, got {}", self.cell));
        }
        Ok(())
    }
}

impl Default for Volume {
    fn default() -> Self {
        Volume::OFF
    }
}
