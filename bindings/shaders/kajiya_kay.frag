#version 450
// Kajiya-Kay hair shading (the paper's eq. 3, METHOD.md) with the wet look: water darkens the
// fibre colour and makes the highlight tighter and brighter. The same constants as the
// software renderer in examples/c/render.c. Writes linear colour; use an sRGB target or
// gamma-encode as below for a UNORM one.

layout(location = 0) in vec3 in_tangent;
layout(location = 1) in vec3 in_to_eye;
layout(location = 2) in float in_wetness;

layout(push_constant) uniform KajiyaKay {
    mat4 view_proj;
    vec4 eye;
    vec4 light;
} pc;

layout(location = 0) out vec4 out_color;

vec3 kajiya_kay(vec3 t, vec3 l, vec3 v, float wet) {
    float lt = dot(l, t);
    float vt = dot(v, t);
    float sin_l = sqrt(max(0.0, 1.0 - lt * lt));
    float sin_v = sqrt(max(0.0, 1.0 - vt * vt));
    float shininess = 30.0 + 120.0 * wet;
    float spec = pow(max(sin_l * sin_v - lt * vt, 0.0), shininess) * (0.25 + 0.75 * wet);
    float darken = 1.0 - 0.6 * wet;
    vec3 base = vec3(0.30, 0.15, 0.06) * darken;
    float diffuse = 0.2 + 0.8 * sin_l;
    return base * diffuse + spec * vec3(1.0, 1.0, 0.95);
}

void main() {
    vec3 t = normalize(in_tangent);
    vec3 v = normalize(in_to_eye);
    vec3 c = kajiya_kay(t, normalize(pc.light.xyz), v, clamp(in_wetness, 0.0, 1.0));
    out_color = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}
