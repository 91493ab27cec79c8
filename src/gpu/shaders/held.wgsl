// Held water on the GPU (cpu/held.rs, physics/wet.rs; docs/WET_MODEL.md §1, §3, §4, §7): each
// point's water in whole quanta, the step's point records with the water's mass and limpness
// (wet_params), soaking, drying, and the saturation the vertices show. Every amount moved is a
// whole number of quanta; totals go to the ledger block with integer atomics, so the ledger is
// exact whatever order the invocations run in.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<storage, read> points: array<Point>;
@group(0) @binding(2) var<storage, read_write> points_wet: array<Point>;
@group(0) @binding(3) var<storage, read_write> held: array<u32>;
@group(0) @binding(4) var<storage, read> capacity: array<u32>;
@group(0) @binding(5) var<storage, read> dry_mass: array<f32>;
@group(0) @binding(6) var<storage, read_write> state: array<State>;
// 64-bit counts as (lo, hi) pairs: [HELD_ADDED] soaked in, [HELD_EVAPORATED] dried off.
@group(0) @binding(7) var<storage, read_write> ledger: array<atomic<u32>, HELD_LEDGER_WORDS>;
@group(0) @binding(8) var<storage, read> soak_target: array<u32>;

// This workgroup's share of a ledger count, (lo, hi): summed here first so one invocation per
// workgroup touches the ledger.
var<workgroup> part_lo: atomic<u32>;
var<workgroup> part_hi: atomic<u32>;

// wet::saturation: held over capacity (0 where a point holds nothing).
fn saturation(q: u32, c: u32) -> f32 {
    if (c > 0u) {
        return f32(q) / f32(c);
    }
    return 0.0;
}

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

// Writes point i's saturation, at most 1, as its wetness.
fn show_saturation(i: u32) {
    state[i].x.w = min(saturation(held[i], capacity[i]), 1.0);
}

// Pass wet_params (cpu/held.rs `refresh_params`), once per step before the substeps: each free
// point's inverse mass from its dry mass plus its water (§3); each bend spring's stiffness
// scaled by the mean saturation of its two ends (§4). A dry point keeps its dry record.
@compute @workgroup_size(WG)
fn wet_params(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
              @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points) {
        return;
    }
    var pt = points[i];
    let q = held[i];
    if (pt.inv_mass != 0.0 && q != 0u) {
        pt.inv_mass = 1.0 / (dry_mass[i] + f32(q) * WATER_QUANTUM);
    }
    if (P.wet_bend_ratio < 1.0 && i + 2u <= pt.last) {
        let s = saturation(q, capacity[i]) + saturation(held[i + 2u], capacity[i + 2u]);
        if (s != 0.0) {
            pt.bend_k = pt.bend_k * bend_scale(0.5 * s);
        }
    }
    points_wet[i] = pt;
}

// Soaking (cpu/held.rs `soak`): each point up to its target, never down; what is added is
// booked as added.
@compute @workgroup_size(WG)
fn soak(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
        @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.points) {
        let q = held[i];
        let t = soak_target[i];
        if (q < t) {
            held[i] = t;
            part_add(t - q);
        }
        show_saturation(i);
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
// k = (1 / dry_time) (1 + sqrt(|wind - v| / dry_air_speed)).
@compute @workgroup_size(WG)
fn dry(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
       @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.points) {
        let q = held[i];
        if (q > 0u) {
            let u = length(P.wind.xyz - state[i].v.xyz);
            let k = (1.0 + sqrt(u / P.dry_air_speed)) / P.dry_time;
            let e = evaporate(q, k, P.dt);
            held[i] = q - e;
            part_add(e);
        }
    }
    part_flush(lid, HELD_EVAPORATED);
}

// Pass saturation (cpu/held.rs `saturation_into`), after the step's held-water passes: the
// wetness each vertex shows.
@compute @workgroup_size(WG)
fn saturation_out(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                  @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i < P.points) {
        show_saturation(i);
    }
}
