// Kajiya-Kay hair strands with the wet look, for wgpu hosts: the same shading as
// kajiya_kay.vert/.frag (see there for the vertex layout). Bind the constants at group 0,
// binding 0, and draw the vertex buffer as a line list.

struct KajiyaKay {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light: vec4<f32>,
}

@group(0) @binding(0) var<uniform> kk: KajiyaKay;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) tangent: vec3<f32>,
    @location(2) wetness: f32,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) tangent: vec3<f32>,
    @location(1) to_eye: vec3<f32>,
    @location(2) wetness: f32,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var o: VertexOut;
    o.clip = kk.view_proj * vec4<f32>(v.position, 1.0);
    o.tangent = v.tangent;
    o.to_eye = kk.eye.xyz - v.position;
    o.wetness = v.wetness;
    return o;
}

fn kajiya_kay(t: vec3<f32>, l: vec3<f32>, v: vec3<f32>, wet: f32) -> vec3<f32> {
    let lt = dot(l, t);
    let vt = dot(v, t);
    let sin_l = sqrt(max(0.0, 1.0 - lt * lt));
    let sin_v = sqrt(max(0.0, 1.0 - vt * vt));
    let shininess = 30.0 + 120.0 * wet;
    let spec = pow(max(sin_l * sin_v - lt * vt, 0.0), shininess) * (0.25 + 0.75 * wet);
    let base = vec3<f32>(0.30, 0.15, 0.06) * (1.0 - 0.6 * wet);
    let diffuse = 0.2 + 0.8 * sin_l;
    return base * diffuse + spec * vec3<f32>(1.0, 1.0, 0.95);
}

@fragment
fn fs_main(i: VertexOut) -> @location(0) vec4<f32> {
    let c = kajiya_kay(normalize(i.tangent), normalize(kk.light.xyz), normalize(i.to_eye), clamp(i.wetness, 0.0, 1.0));
    return vec4<f32>(pow(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)), vec3<f32>(1.0 / 2.2)), 1.0);
}
