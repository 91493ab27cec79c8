//! Guides and followers (docs/GUIDES.md): which strands are simulated, how the others follow
//! them, and how the simulated fraction changes at run time. Off unless asked for; then the
//! backend simulates only the guides and writes every strand's vertices from them.

use crate::error::{check_non_negative, check_positive, invalid, Result};

/// Which strands of a groom are guides (simulated); the others follow them.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum GuideChoice {
    /// Every strand is simulated; no followers (the default: nothing of this feature exists).
    #[default]
    All,
    /// Strands `0, n, 2n, …` in the host's order (`n` ≥ 1; 1 is every strand).
    EveryNth(u32),
    /// `count` strands chosen by wethair spread evenly over the scalp (the first `count` of
    /// the groom's spread order: roots in Morton order, taken in bit-reversed order, so any
    /// prefix is an even subsample).
    Spread(u32),
    /// `count` strands chosen by wethair by clustering the roots (k-means; each cluster's
    /// strand nearest its centre): guides follow the roots' density, so followers sit nearer
    /// their guides where a scalp is uneven (fewer only where a cluster ends empty).
    Cluster(u32),
    /// The host's own guide strands (host strand indices, each at most once).
    Given(Vec<u32>),
}

/// Guides and followers with level of detail (docs/GUIDES.md).
#[derive(Clone, Debug, PartialEq)]
pub struct Guides {
    /// Which strands are guides.
    pub choice: GuideChoice,
    /// Guides per follower: 1 (the nearest guide root) or 3 (the three nearest, weighted by
    /// inverse root distance).
    pub per_follower: u32,
    /// How far a wet follower closes on its nearest guide, 0..=1: at saturation `s` its offset
    /// from the guide shrinks by `clump · s` and its weight moves to the nearest guide by the
    /// same share (clumps look dense though only guides carry water).
    pub clump: f32,
    /// The fraction of the guides simulated at the start, (0, 1]
    /// ([`crate::Simulation::set_guide_fraction`] changes it at run time).
    pub fraction: f32,
    /// Seconds over which a change of the simulated fraction blends the output from the old
    /// guides to the new (no pops); 0 switches at once.
    pub blend_time: f32,
}

impl Guides {
    /// Off: every strand simulated.
    pub const ALL: Guides = Guides {
        choice: GuideChoice::All,
        per_follower: 3,
        clump: 0.8,
        fraction: 1.0,
        blend_time: 0.25,
    };

    /// Every `n`-th strand a guide, the documented defaults otherwise.
    pub fn every_nth(n: u32) -> Guides {
        Guides {
            choice: GuideChoice::EveryNth(n),
            ..Guides::ALL
        }
    }

    /// Whether some strands follow rather than being simulated (or the fraction can change).
    pub fn enabled(&self) -> bool {
        self.choice != GuideChoice::All
    }

    /// Checks every field by name ([`Guides::check_strands`] checks the given indices).
    pub fn validate(&self) -> Result<()> {
        if !matches!(self.per_follower, 1 | 3) {
            return Err(invalid!(
                "guides.per_follower must be 1 or 3, got {}",
                self.per_follower
            ));
        }
        check_non_negative("guides.clump", self.clump)?;
        if self.clump > 1.0 {
            return Err(invalid!("guides.clump must be in [0, 1], got {}", self.clump));
        }
        check_positive("guides.fraction", self.fraction)?;
        if self.fraction > 1.0 {
            return Err(invalid!("guides.fraction must be in (0, 1], got {}", self.fraction));
        }
        check_non_negative("guides.blend_time", self.blend_time)?;
        match &self.choice {
            GuideChoice::All => {}
            GuideChoice::EveryNth(0) => return Err(invalid!("guides: every n-th strand needs n >= 1")),
            GuideChoice::EveryNth(_) => {}
            GuideChoice::Spread(0) => return Err(invalid!("guides: a spread choice needs at least one guide")),
            GuideChoice::Spread(_) => {}
            GuideChoice::Cluster(0) => return Err(invalid!("guides: a cluster choice needs at least one guide")),
            GuideChoice::Cluster(_) => {}
            GuideChoice::Given(list) if list.is_empty() => return Err(invalid!("guides: the given list is empty")),
            GuideChoice::Given(_) => {}
        }
        Ok(())
    }

    /// Checks the given guide indices against a groom of `strands` strands.
    pub fn check_strands(&self, strands: usize) -> Result<()> {
        if let GuideChoice::Given(list) = &self.choice {
            let mut seen = vec![false; strands];
            for &s in list {
                let Some(x) = seen.get_mut(s as usize) else {
                    return Err(invalid!("guides: strand {s} is past the groom's {strands} strands"));
                };
                if *x {
                    return Err(invalid!("guides: strand {s} is given twice"));
                }
                *x = true;
            }
        }
        Ok(())
    }
}

impl Default for Guides {
    fn default() -> Self {
        Guides::ALL
    }
}
