#version 450
// The viewer's flat colour (water, text), from the push constants of viewer_flat.vert.

layout(push_constant) uniform Flat {
    mat4 view_proj;
    vec4 color;
    vec4 params;
} pc;

layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(pc.color.rgb, 1.0);
}
