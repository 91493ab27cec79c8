// SDF colliders (physics/sdf.rs): the trilinear distance and gradient of a grid, and the push
// along the gradient. `pipelines.rs` prepends NSDF (the scene's SDF count) and appends the hair
// or the water entry point. Each substep's placements come in `SS` (a uniform at the
// substep's offset); every grid's samples lie in `sdf_values`, from its `dims.w`.

struct SdfSubstep {
    sdfs: array<Sdf, NSDF>,
}

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<uniform> SS: SdfSubstep;
@group(0) @binding(2) var<storage, read> sdf_values: array<f32>;

// Trilinear distance (x) and gradient (yzw) of grid s at p (grid frame), as `Sdf::sample`;
// x = 1 (no contact) outside the grid.
fn sdf_sample(s: Sdf, p: vec3<f32>) -> vec4<f32> {
    let g = (p - s.origin.xyz) / s.hi.w;
    let top = vec3<f32>(s.dims.xyz - vec3<u32>(1u));
    if (!(all(g >= vec3<f32>(0.0)) && all(g <= top))) {
        return vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    let i = min(vec3<u32>(g), s.dims.xyz - vec3<u32>(2u));
    let f = g - vec3<f32>(i);
    let sx = s.dims.x;
    let sy = s.dims.x * s.dims.y;
    let b = s.dims.w + i.x + sx * i.y + sy * i.z;
    let c = array<f32, 8>(
        sdf_values[b],
        sdf_values[b + 1u],
        sdf_values[b + sx],
        sdf_values[b + sx + 1u],
        sdf_values[b + sy],
        sdf_values[b + sy + 1u],
        sdf_values[b + sy + sx],
        sdf_values[b + sy + sx + 1u],
    );
    let r = trilinear(c, f);
    return vec4<f32>(r.x, r.yzw / s.hi.w);
}

// Pushes a point out of placed grid s (`collide_sdf_point`): along the gradient by the depth
// over the gradient's length, velocity answered as at an analytic collider.
fn collide_sdf(x: ptr<function, vec3<f32>>, v: ptr<function, vec3<f32>>, s: Sdf, friction: f32) {
    let p = *x;
    if (!(all(p >= s.lo.xyz) && all(p <= s.hi.xyz))) {
        return;
    }
    let q = vec3<f32>(dot(s.gx.xyz, p) + s.gx.w, dot(s.gy.xyz, p) + s.gy.w, dot(s.gz.xyz, p) + s.gz.w);
    let r = sdf_sample(s, q);
    if (r.x >= 0.0) {
        return;
    }
    let g = r.yzw;
    let gw = vec3<f32>(dot(s.wx.xyz, g), dot(s.wy.xyz, g), dot(s.wz.xyz, g));
    let lw = sqrt(dot(gw, gw));
    var n = vec3<f32>(0.0, 0.0, 1.0);
    if (lw > 0.0 && !non_finite(1.0 / lw)) {
        n = gw * (1.0 / lw);
    }
    let len = sqrt(dot(g, g));
    var depth = -r.x;
    if (len > 1e-6) {
        depth = -r.x / len;
    }
    let out = p + n * (depth * s.lo.w);
    *x = out;
    // Relative to the surface where it moves (collide.rs `respond_moving`).
    let vc = vec3<f32>(dot(s.vx.xyz, out) + s.vx.w, dot(s.vy.xyz, out) + s.vy.w, dot(s.vz.xyz, out) + s.vz.w);
    let vv = *v - vc;
    let vn = dot(vv, n);
    let into = min(vn, 0.0);
    let tang = vv - n * vn;
    *v = vc + (vv - n * into - tang * friction);
}
