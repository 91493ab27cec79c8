#version 450
// The viewer's flat-coloured geometry in Vulkan: water particles (points, world space) and the
// overlay's text (triangles, a 2D position in clip space; z and w fill in as 0 and 1).
// Push constants share the Kajiya-Kay block's 96-byte layout so one pipeline layout serves all.

layout(location = 0) in vec3 in_position;

layout(push_constant) uniform Flat {
    mat4 view_proj; // world (or overlay) -> clip
    vec4 color;     // rgb: the colour written
    vec4 params;    // x: point size in pixels
} pc;

void main() {
    gl_Position = pc.view_proj * vec4(in_position, 1.0);
    gl_PointSize = pc.params.x;
}
