#version 450
// Kajiya-Kay hair strands, vertex stage. Draw wethair's vertex buffer as a line list (an index
// pair per segment of each strand) or line strips with primitive restart between strands.
// Vertex layout (WetHairVulkanBuffer / WetHairVertexLayout; default attributes):
//   location 0: position, vec3, R32G32B32_SFLOAT, byte offset position_offset
//   location 1: tangent,  vec3, R32G32B32_SFLOAT, byte offset tangent_offset (unit, root to tip)
//   location 2: wetness,  float, R32_SFLOAT,      byte offset wetness_offset (0 dry .. 1 soaked)
// stride = stride_bytes (28 with all three).

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_tangent;
layout(location = 2) in float in_wetness;

// 96 bytes: fits every implementation's 128-byte push-constant minimum.
layout(push_constant) uniform KajiyaKay {
    mat4 view_proj;   // world -> clip
    vec4 eye;         // xyz: camera position (world)
    vec4 light;       // xyz: unit direction towards the light (world); w: unused
} pc;

layout(location = 0) out vec3 out_tangent;
layout(location = 1) out vec3 out_to_eye;
layout(location = 2) out float out_wetness;

void main() {
    gl_Position = pc.view_proj * vec4(in_position, 1.0);
    out_tangent = in_tangent;
    out_to_eye = pc.eye.xyz - in_position;
    out_wetness = in_wetness;
}
