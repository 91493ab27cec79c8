// Held water on the GPU (cpu/held.rs, physics/wet.rs; docs/WET_MODEL.md §1, §3, §4, §6, §7):
// each point's water in whole quanta, the step's point records with the water's mass and
// limpness (wet_params), soaking, flow along the strands, drip, drying, and the saturation the
// vertices show. Every amount moved is a
// whole number of quanta; totals go to the ledger block with integer atomics, so the ledger is
// exact whatever order the invocations run in.

// Group 0, every held-water kernel: the step's parameters, the dry point records, the water,
// capacities, and the state that holds the step's result.
@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<storage, read> points: array<Point>;
// Atomic because absorption's remainder goes to a point chosen by a particle (absorb_finish);
// elsewhere each point's count is read and written by its own invocation.
@group(0) @binding(2) var<storage, read_write> held: array<atomic<u32>>;
// Each point's capacity, then (from P.points on) each point's hold limit: hold_limit.
@group(0) @binding(3) var<storage, read> capacity: array<u32>;
@group(0) @binding(4) var<storage, read_write> state: array<State>;
// Group 1, wet_params, soak, dry and saturation_out: the point records the hair kernels read,
// dry masses, the ledger (64-bit counts as (lo, hi) pairs: [HELD_ADDED] soaked in,
// [HELD_EVAPORATED] dried off), soaking's per-point targets.
@group(1) @binding(0) var<storage, read_write> points_wet: array<Point>;
@group(1) @binding(1) var<storage, read> dry_mass: array<f32>;
@group(1) @binding(2) var<storage, read_write> ledger: array<atomic<u32>, HELD_LEDGER_WORDS>;
@group(1) @binding(3) var<storage, read> soak_target: array<u32>;
// Group 1 of pass wet_params alone, whose layout leaves out bindings 2 and 3 (so that the pass
// binds eight storage buffers, wgpu's default limit): per point 1 where points_wet holds a
// record the water changed, else 0; each point's velocity at the step's start (group 2's
// v0, bound here too; a one-element placeholder without flow).
@group(1) @binding(4) var<storage, read_write> wet_record: array<u32>;
@group(1) @binding(5) var<storage, read_write> v_start: array<vec4<f32>>;
// Group 2, flow and drip: each point's velocity at the step's start (wet_params writes
// it; flow and drip read it for the point's acceleration over the step); flow's and drip's
// scratch (per point the drop it sheds, quanta, then per drip_count
// workgroup its drops and, after drip_scan, the particle slot of its first); the particles
// (drops go after the live ones) and the water state block.
@group(2) @binding(0) var<storage, read_write> v0: array<vec4<f32>>;
@group(2) @binding(1) var<storage, read_write> drip_scratch: array<u32>;
@group(2) @binding(2) var<storage, read_write> particles: array<Particle>;
@group(2) @binding(3) var<storage, read_write> water_state: array<atomic<u32>, WATER_STATE_WORDS>;
// Group 3, absorb and absorb_finish: the particles in grid order, the grid, absorption's
// per-particle scratch (buffers::absorb_words), and the substep's output state.
@group(3) @binding(0) var<storage, read_write> sorted: array<Particle>;
@group(3) @binding(1) var<storage, read> grid: array<u32>;
@group(3) @binding(2) var<storage, read_write> absorb_scratch: array<atomic<u32>>;
@group(3) @binding(3) var<storage, read_write> state_out: array<State>;

// This workgroup's share of a ledger count, (lo, hi): summed here first so one invocation per
// workgroup touches the ledger.
var<workgroup> part_lo: atomic<u32>;
var<workgroup> part_hi: atomic<u32>;

// wet::bend_scale: 1 dry, wet_bend_ratio saturated, linear between.
fn bend_scale(s: f32) -> f32 {
    return 1.0 - (1.0 - P.wet_bend_ratio) * clamp(s, 0.0, 1.0);
}

// Adds `x` quanta to this workgroup's part, carrying into the high word.
fn part_add(x: u32) {
    if (x == 0u) {
        return;
    }
    let old = atomicAdd(&part_lo, x);
    if (old + x < old) {
        atomicAdd(&part_hi, 1u);
    }
}

// After every invocation's part_add: the first invocation adds the part to ledger count `at`.
fn part_flush(lid: u32, at: u32) {
    workgroupBarrier();
    if (lid != 0u) {
        return;
    }
    let lo = atomicLoad(&part_lo);
    var hi = atomicLoad(&part_hi);
    if (lo == 0u && hi == 0u) {
        return;
    }
    let old = atomicAdd(&ledger[at], lo);
    if (old + lo < old) {
        hi += 1u;
    }
    if (hi != 0u) {
        atomicAdd(&ledger[at + 1u], hi);
    }
}

// wet::quantum_per_strand of point i's bundle: the water a quantum adds to each strand it
// stands for, kg. Only a guide groom's buffer holds them, after every point's dry mass.
fn quantum_at(i: u32) -> f32 {
    if (HELD_BUNDLES) {
        return dry_mass[HELD_POINTS + i];
    }
    return WATER_QUANTUM;
}

// Point i's hold limit (wet::hold_limit): the limits buffer holds every point's capacity,
// then every point's hold limit. HELD_POINTS (the groom's), not P.points (the points stepped:
// fewer while a lower guide fraction is simulated).
fn hold_limit(i: u32) -> u32 {
    return capacity[HELD_POINTS + i];
}

// wet::running: the water above a point's hold limit, which may run along the strand.
fn running(q: u32, hold: u32) -> u32 {
    return q - min(q, hold);
}

// Writes point i's wetness with water q: its water over its hold limit, at most 1.
fn show_saturation(i: u32, q: u32) {
    state[i].x.w = min(saturation(q, hold_limit(i)), 1.0);
}

// Pass wet_params (cpu/held.rs `refresh_params` and `keep_velocities`), once per step before
// the substeps: each free point's inverse mass from its dry mass plus its water (§3); each
// bend spring's stiffness scaled by the mean saturation of its two ends (§4); with flow, each
// point's velocity at the step's start, for flow's and drip's accelerations (only the
// velocity: a copy of the whole state cost twice the traffic). A point whose ends hold no
// water and whose record is already the dry one reads three words and writes nothing (as the
// CPU skips rows that were and are dry): under light rain that is nearly every point.
@compute @workgroup_size(WG)
fn wet_params(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
              @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points) {
        return;
    }
    // Without flow the buffer is a one-element placeholder and no velocity is kept.
    if (arrayLength(&v_start) == arrayLength(&held)) {
        v_start[i] = state[i].v;
    }
    let q = atomicLoad(&held[i]);
    var q2 = 0u;
    if (P.wet_bend_ratio < 1.0 && i + 2u < P.points) {
        q2 = atomicLoad(&held[i + 2u]);
    }
    if (q == 0u && q2 == 0u && wet_record[i] == 0u) {
        return;
    }
    var pt = points[i];
    var wet = false;
    if (pt.inv_mass != 0.0 && q != 0u) {
        pt.inv_mass = 1.0 / (dry_mass[i] + f32(q) * quantum_at(i));
        wet = true;
    }
    if (P.wet_bend_ratio < 1.0 && i + 2u <= pt.last) {
        let s = saturation(q, capacity[i]) + saturation(q2, capacity[i + 2u]);
        if (s != 0.0) {
            pt.bend_k = pt.bend_k * bend_scale(0.5 * s);
            wet = true;
        }
    }
    if (wet || wet_record[i] != 0u) {
        // A record the water changes, or the dry record back where it did.
        points_wet[i] = pt;
        wet_record[i] = select(0u, 1u, wet);
    }
}

// Soaking (cpu/held.rs `soak`): each point up to its target, never down; what is added is
// booked as added.
@compute @workgroup_size(WG)
fn soak(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
        @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.points) {
        let q = atomicLoad(&held[i]);
        let t = soak_target[i];
        if (q < t) {
            atomicStore(&held[i], t);
            part_add(t - q);
        }
        show_saturation(i, atomicLoad(&held[i]));
    }
    part_flush(lid, HELD_ADDED);
}

// wet::evaporate: held (1 - e^(-k h)) to nearest, at least one quantum while water and a rate
// are left. 1 - e^(-x) by its series where f32 would cancel.
fn evaporate(q: u32, k: f32, h: f32) -> u32 {
    let x = k * h;
    var frac = 1.0 - exp(-x);
    if (x < 1.0e-2) {
        frac = x * (1.0 - x * (0.5 - x * (1.0 / 6.0)));
    }
    let e = u32(round(f32(q) * frac));
    if (e == 0u && q > 0u && frac > 0.0) {
        return 1u;
    }
    return min(e, q);
}

// Pass dry (cpu/held.rs `dry`), once per step: each point loses water at
// k = (1 / dry_time) (1 + sqrt(|wind - v| / dry_air_speed)). Then the saturation that
// saturation_out would write, from the water left: the same law, without a second pass over
// every point (the CPU's settle likewise shows each block's saturation after its drying).
@compute @workgroup_size(WG)
fn dry(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
       @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.points) {
        var q = atomicLoad(&held[i]);
        if (q > 0u) {
            let u = length(P.wind.xyz - state[i].v.xyz);
            let k = (1.0 + sqrt(u / P.dry_air_speed)) / P.dry_time;
            let e = evaporate(q, k, P.dt);
            q -= e;
            atomicStore(&held[i], q);
            part_add(e);
        }
        show_saturation(i, q);
    }
    part_flush(lid, HELD_EVAPORATED);
}

// Gravity less point i's acceleration over the step (gravity alone without flow, as on the
// CPU, which keeps no step-start velocities then).
fn g_eff(i: u32) -> vec3<f32> {
    if (P.flow_speed > 0.0) {
        return P.g.xyz - (state[i].v.xyz - v0[i].xyz) / P.dt;
    }
    return P.g.xyz;
}

// wet::runs_toward's weight: how far along t the effective gravity points, over |g| (0 when
// it points away).
fn along(ge: vec3<f32>, t: vec3<f32>, g_len: f32) -> f32 {
    let a = dot(ge, t);
    if (a > 0.0) {
        return a / g_len;
    }
    return 0.0;
}

fn unit_or_zero(d: vec3<f32>) -> vec3<f32> {
    let l = length(d);
    if (l > 0.0) {
        return d / l;
    }
    return vec3<f32>(0.0);
}

// The share of a point's running water that crosses the segment d (from the point to its
// neighbour) in a step under effective gravity ge: dt (flow_speed / |d|) along(ge, d / |d|)
// (wet.rs `segment_along` times the step's rate); 0 for a segment of no length.
fn flow_rate(d: vec3<f32>, ge: vec3<f32>, g_len: f32) -> f32 {
    let l = length(d);
    if (l > 0.0) {
        return P.dt * P.flow_speed / l * along(ge, d / l, g_len);
    }
    return 0.0;
}

// floor(w q), at most q: the part of q quanta a share w sends. A segment far shorter than
// dt flow_speed, or a point flung hard, makes w huge (or inf, or NaN): the float is cut below
// 2^32 before it becomes a count, and NaN sends nothing.
fn flow_part(w: f32, q: u32) -> u32 {
    if (!(w > 0.0)) {
        return 0u;
    }
    return min(u32(min(floor(w * f32(q)), 4294967040.0)), q);
}

// Pass flow (wet::flow_strand), once per step, in two kernels over the points (one
// invocation per point, so a warp reads neighbouring points: one per strand left fifteen of
// sixteen lanes idle and read the strands' points scattered). Each end of a segment of length
// l sends floor(dt (flow_speed / l) running along) across it, `running` its water above its
// hold limit at the step's start, so the water moves flow_speed m/s down a vertical strand
// however finely it is sampled; a point asked for more than may run sends all that may,
// shared in proportion. Every transfer is one integer from one point to its neighbour.

// What point i, with q quanta that may run, sends to its previous (x) and next (y)
// neighbour, before the inflow bound.
fn flow_sends(i: u32, pt: Point, q: u32, g_len: f32) -> vec2<u32> {
    if (q == 0u) {
        return vec2<u32>(0u);
    }
    let ge = g_eff(i);
    let x = state[i].x.xyz;
    var to_prev = 0u;
    var to_next = 0u;
    if (i > pt.first) {
        to_prev = flow_part(flow_rate(state[i - 1u].x.xyz - x, ge, g_len), q);
    }
    if (i < pt.last) {
        to_next = flow_part(flow_rate(state[i + 1u].x.xyz - x, ge, g_len), q);
    }
    let out = f32(to_prev) + f32(to_next);
    if (out > f32(q)) {
        let share = f32(q) / out;
        to_prev = min(u32(floor(f32(to_prev) * share)), q);
        to_next = min(u32(floor(f32(to_next) * share)), q - to_prev);
    }
    return vec2<u32>(to_prev, to_next);
}

// Pass flow, part 1: what each point sends each way, into drip's scratch (two words a point;
// drip comes after and writes over them). wet::flow_inflow_bound: each neighbour gives a
// point at most half its room below the count's end, so its count cannot wrap.
@compute @workgroup_size(WG)
fn flow_send(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
             @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points) {
        return;
    }
    let pt = points[i];
    let g_len = length(P.g.xyz);
    var send = vec2<u32>(0u);
    if (g_len > 0.0) {
        send = flow_sends(i, pt, running(atomicLoad(&held[i]), hold_limit(i)), g_len);
    }
    if (send.x != 0u) {
        send.x = min(send.x, (0xffffffffu - atomicLoad(&held[i - 1u])) / 2u);
    }
    if (send.y != 0u) {
        send.y = min(send.y, (0xffffffffu - atomicLoad(&held[i + 1u])) / 2u);
    }
    drip_scratch[2u * i] = send.x;
    drip_scratch[2u * i + 1u] = send.y;
}

// Pass flow, part 2: each point's water less what it sends, plus what its neighbours send it.
@compute @workgroup_size(WG)
fn flow_take(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
             @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points) {
        return;
    }
    let pt = points[i];
    var gain = 0u;
    if (i > pt.first) {
        gain += drip_scratch[2u * (i - 1u) + 1u];
    }
    if (i < pt.last) {
        gain += drip_scratch[2u * (i + 1u)];
    }
    let lose = drip_scratch[2u * i] + drip_scratch[2u * i + 1u];
    if (gain != 0u || lose != 0u) {
        atomicStore(&held[i], atomicLoad(&held[i]) - lose + gain);
    }
}

// wet::drip: the excess over the hold limit c once it reaches the smallest drop.
fn drip_excess(q: u32, c: u32) -> u32 {
    if (q <= c) {
        return 0u;
    }
    let e = q - c;
    if (e >= P.min_drop) {
        return e;
    }
    return 0u;
}

// Whether water at point i runs on to a neighbour under effective gravity ge.
fn runs_on(i: u32, pt: Point, ge: vec3<f32>) -> bool {
    let x = state[i].x.xyz;
    return (i > pt.first && dot(ge, state[i - 1u].x.xyz - x) > 0.0)
        || (i < pt.last && dot(ge, state[i + 1u].x.xyz - x) > 0.0);
}

// Drops in this drip_count workgroup.
var<workgroup> drops: atomic<u32>;
// The particle count before the step's drops (drip_scan).
var<private> drip_base: u32;

// The point a drip_count or drip_emit invocation stands for.
fn drip_point(wid: vec3<u32>, nwg: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * nwg.x + wid.x) * DRIP_WG + lid;
}

// The scan's block sums (scan.wgsl `scan_block_sums`): drip_count's drops per workgroup, after
// the per-point drops; written back as each workgroup's first particle slot.
fn block_sum(k: u32) -> u32 {
    return drip_scratch[P.points + k];
}

fn set_block_sum(k: u32, v: u32) {
    drip_scratch[P.points + k] = drip_base + v;
}

// Pass drip, part 1 (cpu/held.rs `drip`): each point's drop (its excess, where the water
// cannot run on), and each workgroup's count of drops.
@compute @workgroup_size(DRIP_WG)
fn drip_count(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
              @builtin(local_invocation_index) lid: u32) {
    let i = drip_point(wid, nwg, lid);
    if (lid == 0u) {
        atomicStore(&drops, 0u);
    }
    workgroupBarrier();
    if (i < P.points) {
        var q = drip_excess(atomicLoad(&held[i]), hold_limit(i));
        // The point's record only for a point with a drop (nearly none): read for every
        // point, it was most of the pass's bytes.
        if (q > 0u && P.flow_speed > 0.0 && runs_on(i, points[i], g_eff(i))) {
            q = 0u;
        }
        drip_scratch[i] = q;
        if (q > 0u) {
            atomicAdd(&drops, 1u);
        }
    }
    workgroupBarrier();
    if (lid == 0u) {
        drip_scratch[P.points + wid.y * nwg.x + wid.x] = atomicLoad(&drops);
    }
}

// Pass drip, part 2 (one workgroup): each drip_count workgroup's first particle slot, in point
// order after the live particles (so drops are numbered as the CPU numbers them); the count
// grows by the drops that fit.
@compute @workgroup_size(256)
fn drip_scan(@builtin(local_invocation_index) lid: u32) {
    drip_base = atomicLoad(&water_state[WATER_HELD]);
    let total = scan_block_sums(lid, (P.points + DRIP_WG - 1u) / DRIP_WG);
    storageBarrier();
    if (lid == 0u) {
        atomicStore(&water_state[WATER_HELD], min(drip_base + total, P.capacity));
    }
}

// Pass drip, part 3: each drop becomes a particle with its point's velocity, r_max below the
// point along the effective gravity (just out of its pull); when the water is full the excess
// waits on the hair.
@compute @workgroup_size(DRIP_WG)
fn drip_emit(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
             @builtin(local_invocation_index) lid: u32) {
    let i = drip_point(wid, nwg, lid);
    var q = 0u;
    if (i < P.points) {
        q = drip_scratch[i];
    }
    let one = select(0u, 1u, q > 0u);
    scan_inclusive(lid, one);
    if (q == 0u) {
        return;
    }
    let slot = drip_scratch[P.points + wid.y * nwg.x + wid.x] + scan[lid] - one;
    if (slot >= P.capacity) {
        return;
    }
    let s = state[i];
    let x = s.x.xyz + P.r_max * unit_or_zero(g_eff(i));
    particles[slot] = Particle(x, q, s.v.xyz, 0u);
    atomicSub(&held[i], q);
}

// Takes up to `g` quanta from particle k, which holds `q`; returns what it took. While the
// grants sum to at most the particle's water (they do: see absorb) nothing is clipped and the
// order of takers does not matter.
fn take_from(k: u32, q: u32, g: u32) -> u32 {
    let at = k * ABS_WORDS + ABS_GIVEN;
    var old = atomicLoad(&absorb_scratch[at]);
    var taken = 0u;
    loop {
        let t = min(g, q - min(old, q));
        if (t == 0u) {
            break;
        }
        let r = atomicCompareExchangeWeak(&absorb_scratch[at], old, old + t);
        if (r.exchanged) {
            taken = t;
            break;
        }
        old = r.old_value;
    }
    return taken;
}

// Pass absorb (cpu/water.rs `Water::absorb`; docs/WET_MODEL.md §2), per hair point after the
// substep's hair kernel: each demand it made in adhesion (the same function of the same
// inputs: its position and saturation at the substep's start) is granted in full while the
// particle's demands sum to at most its water, else its share, rounded down after a margin
// that keeps f32 rounding from granting more than the exact share. The point takes its grants
// and shows its new saturation; the lowest index among the largest demanders is noted for the
// remainder.
@compute @workgroup_size(WG)
fn absorb(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
          @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points) {
        return;
    }
    // Only a point the hair kernel marked had a particle within reach, so only it can have
    // asked: the rest leave after one word shared by 32 points, not their state.
    let word = near_word(i);
    let bit = near_bit(i);
    if ((atomicLoad(&absorb_scratch[word]) & bit) == 0u) {
        return;
    }
    atomicAnd(&absorb_scratch[word], ~bit);
    let s = state[i];
    // Where adhesion asked (BDF2's x + h v): the same inputs give the same demands.
    let x = explicit_point(s);
    let sat = s.x.w;
    var span: Span;
    if (sat >= 1.0 || !near_span(x, P.r_max, &span)) {
        return;
    }
    let r2 = P.r_max * P.r_max;
    // The point takes each grant up to its room below its hold limit at the substep's start
    // (wet::hold_room), and in all up to HELD_LIMIT (wet::HELD_LIMIT); the particle keeps the
    // rest.
    // Only this invocation adds to held[i] during the pass (remainders come after).
    let held0 = atomicLoad(&held[i]);
    let room0 = hold_room(held0, hold_limit(i));
    let take = absorb_take_at(i);
    var got = 0u;
    for (var j = 0; j < span_cells(span); j++) {
        let c = span_cell(span, j);
        let run = cell_run(c);
        for (var k = run.x; k < run.y; k++) {
            let y = sorted[k].x.xyz;
            let d = y - x;
            let d2 = dot(d, d);
            if (d2 > r2 || !in_cell(y, c)) {
                continue;
            }
            let q = sorted[k].mass;
            let demand = absorb_demand(q, d2, sat, take);
            if (demand == 0u) {
                continue;
            }
            let at = k * ABS_WORDS;
            let lo = atomicLoad(&absorb_scratch[at + ABS_TOTAL]);
            let hi = atomicLoad(&absorb_scratch[at + ABS_TOTAL + 1u]);
            var g = demand;
            if (hi != 0u || lo > q) {
                let total = f32(hi) * 4294967296.0 + f32(lo);
                g = u32(floor(f32(demand) * (f32(q) / total) * (1.0 - 4.0e-7)));
            }
            g = min(min(g, room0), HELD_LIMIT - min(held0 + got, HELD_LIMIT));
            got += take_from(k, q, g);
            if (demand == atomicLoad(&absorb_scratch[at + ABS_BEST])) {
                atomicMax(&absorb_scratch[at + ABS_POINT], ~i);
            }
        }
    }
    if (got > 0u) {
        let q = atomicAdd(&held[i], got) + got;
        state_out[i].x.w = min(saturation(q, hold_limit(i)), 1.0);
    }
}

// Pass absorb, part 2, per particle: a particle left with less than absorb_last quanta goes
// whole to its largest demander (absorption is exponential and would never finish); the
// particle keeps what is left (an emptied one is removed at the step's end), noted in `left`
// for water_integrate, which moves it with its `mass` at the substep's start first; and its
// scratch record is cleared.
@compute @workgroup_size(WG)
fn absorb_finish(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                 @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k >= grid[G_COUNT]) {
        return;
    }
    let at = k * ABS_WORDS;
    let q = sorted[k].mass;
    var left = q - min(atomicLoad(&absorb_scratch[at + ABS_GIVEN]), q);
    let best = atomicLoad(&absorb_scratch[at + ABS_BEST]);
    let point = ~atomicLoad(&absorb_scratch[at + ABS_POINT]);
    if (best > 0u && left > 0u && left < P.absorb_last && point < P.points) {
        atomicAdd(&held[point], left);
        left = 0u;
    }
    sorted[k].left = left;
    // The record is clear for the next substep.
    for (var w = 0u; w < ABS_WORDS; w++) {
        atomicStore(&absorb_scratch[at + w], 0u);
    }
}

// Pass saturation (cpu/held.rs `saturation_into`), after the step's held-water passes when
// none dries (dry writes it then): the wetness each vertex shows.
@compute @workgroup_size(WG)
fn saturation_out(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                  @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.points) {
        show_saturation(i, atomicLoad(&held[i]));
    }
}
