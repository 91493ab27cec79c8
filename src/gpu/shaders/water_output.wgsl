// Pass write_water_vertices (the GPU side of Simulation::water_positions, for a host that
// draws the particles from the shared buffers): the held particles' positions (w = 1) and the
// arguments of the host's indirect draw, a VkDrawIndirectCommand with vertexCount = the
// particles held. Nothing is written once a step has failed, so no NaN reaches the buffer.

@group(0) @binding(0) var<storage, read> particles: array<Particle>;
@group(0) @binding(1) var<storage, read> water_state: array<u32, 4>;
@group(0) @binding(2) var<storage, read> status: array<u32, 4>;
@group(0) @binding(3) var<storage, read_write> water_vertices: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> water_draw: array<u32, 4>;

@compute @workgroup_size(WG)
fn write_water_vertices(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                        @builtin(local_invocation_index) lid: u32) {
    if (status[STATUS_FLAGS] != 0u) {
        return;
    }
    let i = linear_id(wid, nwg, lid);
    let n = min(water_state[WATER_HELD], arrayLength(&water_vertices));
    if (i == 0u) {
        water_draw[0] = n;
        water_draw[1] = 1u;
        water_draw[2] = 0u;
        water_draw[3] = 0u;
    }
    if (i < n) {
        water_vertices[i] = vec4<f32>(particles[i].x.xyz, 1.0);
    }
}
