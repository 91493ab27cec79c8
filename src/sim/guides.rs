//! Guides and followers at the simulation's level (docs/GUIDES.md): the guide groom the
//! backend simulates, each host strand's binding, and the simulated fraction's changes at run
//! time. A lower fraction keeps the first guides of the spread order; the strands it drops
//! keep being stepped while the output blends from the old bindings to the new over
//! `blend_time`, and a higher fraction starts its new guides where the output showed them, so
//! neither direction pops.

use crate::engine::Engine;
use crate::error::Result;
use crate::groom::Groom;
use crate::params::{GuideChoice, Guides};
use crate::physics::bundles::{bundles, give_back, take_shares};
use crate::physics::follow::{follow_point, follow_velocity, guide_frame_at, head_quat, GuidePoint};
use crate::physics::follow_roots::{root_points, root_strand, OwnRoot};
use crate::physics::followers::{bind, choose, cluster, Follow, Followers, GuideSpan};
use crate::physics::roots::RootFrame;
use glam::{Affine3A, Quat, Vec3};

/// The guides' bookkeeping.
#[derive(Debug)]
pub(super) struct GuideState {
    /// Guide-groom strand → host strand (spread order).
    host_of: Vec<u32>,
    /// Every host strand's root (rest, head space).
    roots: Vec<Vec3>,
    per: u32,
    blend_time: f32,
    /// Guides the simulated fraction keeps.
    active: usize,
    /// Guides the backend steps: `active`, or more while a lower fraction's blend settles.
    stepping: usize,
    /// How far the output has moved from the old bindings to the new, 0..=1.
    blend: f32,
    /// The head's rotation the followers' offsets turn with (the last step's end).
    head: Quat,
    /// What the backend writes the output from.
    data: Followers,
    /// Every host strand's dry mass, kg (what a guide's bundle weighs).
    strand_mass: Vec<f32>,
    /// Each guide's bundle now (`physics/bundles.rs`; 1 for guides not simulated).
    bundle: Vec<f32>,
}

impl GuideState {
    /// The guides of `groom` under `g` (on) and the guide groom the backend simulates;
    /// `skinned_roots` puts every strand's root points on its own root frame.
    pub(super) fn new(groom: &Groom, g: &Guides, skinned_roots: bool) -> Result<(GuideState, Groom)> {
        g.check_strands(groom.strand_count())?;
        let roots = groom.roots();
        let host_of = match &g.choice {
            GuideChoice::All => choose(&roots, |_| true, None),
            GuideChoice::EveryNth(n) => choose(&roots, |s| s % n == 0, None),
            GuideChoice::Spread(c) => choose(&roots, |_| true, Some(*c as usize)),
            GuideChoice::Cluster(c) => {
                let mut is = vec![false; roots.len()];
                cluster(&roots, *c as usize)
                    .into_iter()
                    .for_each(|s| is[s as usize] = true);
                choose(&roots, |s| is[s as usize], None)
            }
            GuideChoice::Given(list) => {
                let mut is = vec![false; roots.len()];
                list.iter().for_each(|&s| is[s as usize] = true);
                choose(&roots, |s| is[s as usize], None)
            }
        };
        let guide_groom = groom.subset(&host_of);
        let spans = (0..host_of.len())
            .map(|e| GuideSpan {
                first: guide_groom.strand_first[e],
                rest: groom.strand_first[host_of[e] as usize],
                count: guide_groom.strand_first[e + 1] - guide_groom.strand_first[e],
                host: host_of[e],
            })
            .collect();
        let mut st = GuideState {
            active: 0,
            stepping: 0,
            blend: 1.0,
            head: Quat::IDENTITY,
            per: g.per_follower,
            blend_time: g.blend_time,
            data: Followers {
                strand_first: groom.strand_first.clone(),
                rest: groom.positions().to_vec(),
                spans,
                follow: Vec::new(),
                from: Vec::new(),
                clump: g.clump,
                root_points: match skinned_roots {
                    true => (0..groom.strand_count())
                        .map(|s| root_points(&groom.pinned()[groom.strand_range(s)]))
                        .collect(),
                    false => Vec::new(),
                },
            },
            strand_mass: (0..groom.strand_count())
                .map(|s| groom.masses()[groom.strand_range(s)].iter().sum())
                .collect(),
            bundle: Vec::new(),
            host_of,
            roots,
        };
        st.active = st.count_for(g.fraction);
        st.stepping = st.active;
        st.data.follow = bind(&st.roots, &st.host_of[..st.active], st.per);
        st.bundle = bundles(&st.data.follow, &st.strand_mass, &st.host_of);
        Ok((st, guide_groom))
    }

    /// Gives the backend each guide's bundle: what its water, and its pull on a drop, stand
    /// for (docs/GUIDES.md "Water").
    pub(super) fn start(&self, engine: &mut dyn Engine) -> Result<()> {
        engine.set_bundles(&self.bundle, None)
    }

    /// The held water follows the hair from the bindings `before` (guides `0..was`
    /// simulated) to the current ones: guides added take their shares, guides dropped give
    /// theirs back; then the new bundles (`physics/bundles.rs`).
    fn move_water(&mut self, was: usize, before: &[Follow], engine: &mut dyn Engine) -> Result<()> {
        let bundle = bundles(&self.data.follow, &self.strand_mass, &self.host_of);
        let mut water = engine.held_water()?;
        if water.is_empty() {
            // No held water to move: the drops' pulls still follow the new bundles.
            self.bundle = bundle;
            return engine.set_bundles(&self.bundle, None);
        }
        let (spans, host_of) = (&self.data.spans, &self.host_of);
        if self.active > was {
            take_shares(
                &mut water,
                was..self.active,
                before,
                &self.bundle,
                spans,
                host_of,
                &self.strand_mass,
            );
        } else {
            give_back(&mut water, self.active..was, &self.data.follow, spans, host_of);
        }
        self.bundle = bundle;
        engine.set_bundles(&self.bundle, Some(&water))
    }

    /// What the backend writes the output from.
    pub(super) fn followers(&self) -> &Followers {
        &self.data
    }

    /// Guides the backend steps now.
    pub(super) fn stepping(&self) -> usize {
        self.stepping
    }

    /// Guides a fraction `f` keeps (at least one).
    pub(super) fn count_for(&self, f: f32) -> usize {
        let n = self.host_of.len();
        ((f as f64 * n as f64).ceil() as usize).clamp(1, n)
    }

    /// The guides simulated now and in all.
    pub(super) fn counts(&self) -> (usize, usize) {
        (self.active, self.host_of.len())
    }

    /// Host strand of each guide, in the guide groom's (spread) order.
    pub(super) fn host_strands(&self) -> &[u32] {
        &self.host_of
    }

    /// Simulates the first `count_for(f)` guides from the next step on. New guides start where
    /// the output shows them now (a blocking read of the guides on the GPU; on their root
    /// frames `roots` with skinned roots); the bindings move to the new guides over
    /// `blend_time`.
    pub(super) fn set_fraction(&mut self, f: f32, roots: &[RootFrame], engine: &mut dyn Engine) -> Result<()> {
        let k = self.count_for(f);
        if k == self.active {
            return Ok(());
        }
        if k > self.active {
            self.seed(self.active..k, roots, engine)?;
        }
        let before = std::mem::replace(&mut self.data.follow, bind(&self.roots, &self.host_of[..k], self.per));
        let was = std::mem::replace(&mut self.active, k);
        self.move_water(was, &before, engine)?;
        self.data.from = before;
        self.blend = 0.0;
        self.stepping = self.stepping.max(k);
        if self.blend_time == 0.0 {
            self.settle();
        }
        engine.set_followers(&self.data)?;
        engine.set_active_strands(self.stepping);
        Ok(())
    }

    /// Starts guides `new` where their current bindings put them (on their own root frames
    /// `roots` with skinned roots): positions, velocities and wetness from the simulated
    /// guides.
    fn seed(&self, new: std::ops::Range<usize>, roots: &[RootFrame], engine: &mut dyn Engine) -> Result<()> {
        let states = engine.point_states()?;
        let d = &self.data;
        let start = |span: &GuideSpan| match roots.is_empty() {
            true => head_quat(self.head),
            false => head_quat(roots[span.host as usize].rotation),
        };
        // Every guide point's position, wetness and frame, as the output's pass guide_frames
        // makes them.
        let mut points: Vec<GuidePoint> = Vec::with_capacity(states.len());
        for span in &d.spans {
            for j in 0..span.count {
                let s = &states[(span.first + j) as usize];
                let frame = guide_frame_at(*span, j, &d.rest, start(span), |p| states[p as usize].0);
                points.push((s.0, s.2, frame, d.rest[(span.rest + j) as usize]));
            }
        }
        let at = |p: u32| points[p as usize];
        let vel = |p: u32| states[p as usize].1;
        let (mut x, mut v, mut w) = (Vec::new(), Vec::new(), Vec::new());
        for e in new.clone() {
            let h = self.host_of[e] as usize;
            let first = d.strand_first[h];
            let n = d.strand_first[h + 1] - first;
            let f = &d.follow[h];
            let at_strand = x.len();
            for i in 0..n {
                let rest_i = d.rest[(first + i) as usize];
                let (p, wet) = follow_point(f, &d.spans, i, n, rest_i, d.clump, &at);
                x.push(p);
                w.push(wet);
                v.push(follow_velocity(f, &d.spans, i, n, &vel));
            }
            if !roots.is_empty() {
                let own = OwnRoot {
                    frame: roots[h],
                    rest_root: d.rest[first as usize],
                    points: d.root_points[h],
                };
                root_strand(&own, n, |i| d.rest[(first + i) as usize], &mut x[at_strand..]);
            }
        }
        engine.seed_strands(new.start as u32, &x, &v, &w)
    }

    /// The blend's end: the old bindings go, and the dropped guides stop being stepped.
    fn settle(&mut self) {
        self.blend = 1.0;
        self.data.from.clear();
        self.stepping = self.active;
    }

    /// Before a step of `dt` that ends with the head at `to` and the roots shown at `roots`
    /// (skinned roots; else empty): moves the blend on (settling when it is done) and poses
    /// the followers.
    pub(super) fn before_step(
        &mut self,
        dt: f32,
        to: &Affine3A,
        roots: &[RootFrame],
        engine: &mut dyn Engine,
    ) -> Result<()> {
        if self.blend < 1.0 {
            self.blend = (self.blend + dt / self.blend_time).min(1.0);
            if self.blend >= 1.0 {
                self.settle();
                engine.set_followers(&self.data)?;
                engine.set_active_strands(self.stepping);
            }
        }
        self.pose(to, roots, engine);
        Ok(())
    }

    /// Poses the followers for the head at `head` and the roots at `roots` (skinned roots;
    /// else empty), and the blend as it stands.
    pub(super) fn pose(&mut self, head: &Affine3A, roots: &[RootFrame], engine: &mut dyn Engine) {
        self.head = head.to_scale_rotation_translation().1;
        engine.pose_followers(self.head, self.blend, roots);
    }

    /// Poses the followers' roots at `roots` (the head and blend as they stand).
    pub(super) fn pose_roots(&mut self, roots: &[RootFrame], engine: &mut dyn Engine) {
        engine.pose_followers(self.head, self.blend, roots);
    }

    /// After a reset: settled, the bindings the fraction keeps.
    pub(super) fn reset(&mut self, head: &Affine3A, roots: &[RootFrame], engine: &mut dyn Engine) -> Result<()> {
        if self.blend < 1.0 {
            self.settle();
            engine.set_followers(&self.data)?;
            engine.set_active_strands(self.stepping);
        }
        self.pose(head, roots, engine);
        Ok(())
    }
}
