/* Writes the vertex buffer a C host reads, as raw little-endian floats, after a fixed run:
 * the paper scene's exact parameters and head sphere (wh_create_paper_sim), N strands x 6
 * points on the CPU backend, 40 water particles on a 1 cm grid above the head at frame 0, then FRAMES steps of
 * 1/60 s. The Python package's tests run the same scene through their binding and require
 * the same bytes (bindings/python/tests/test_against_c.py).
 *
 * usage: dump_vertices STRANDS FRAMES OUT.bin */
#include "scene.h"

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: %s STRANDS FRAMES OUT.bin\n", argv[0]);
        return 2;
    }
    uint32_t strands = (uint32_t)atoi(argv[1]);
    int frames = atoi(argv[2]);
    WetHairGroom *groom = NULL;
    wh_check(wethair_groom_create_paper_scene(strands, 6, &groom), "wethair_groom_create_paper_scene");
    WetHairSim *sim = wh_create_paper_sim(groom, 0, WETHAIR_BACKEND_CPU);
    wethair_groom_destroy(groom);
    float pos[40 * 3];
    for (int i = 0; i < 40; i++) { /* exact in float, so any host computes the same */
        pos[3 * i + 0] = ((float)(i % 8) - 3.5f) * 0.01f;
        pos[3 * i + 1] = ((float)(i / 8) - 2.0f) * 0.01f;
        pos[3 * i + 2] = 0.13f;
    }
    wh_check(wethair_sim_add_water(sim, pos, NULL, 40), "wethair_sim_add_water");
    for (int f = 0; f < frames; f++) wh_check(wethair_sim_step(sim, 1.0f / 60.0f), "wethair_sim_step");
    WetHairVertexLayout lay;
    size_t cap, written = 0;
    float *v = wh_vertex_buffer(sim, &lay, &cap);
    wh_check(wethair_sim_get_vertex_buffer(sim, v, cap, &written), "wethair_sim_get_vertex_buffer");
    FILE *f = fopen(argv[3], "wb");
    if (!f || fwrite(v, sizeof *v, written, f) != written || fclose(f) != 0) {
        fprintf(stderr, "cannot write %s\n", argv[3]);
        return 1;
    }
    printf("dump_vertices: %zu floats (%u vertices x %u) after %d frames\n", written, lay.vertex_count,
           lay.stride_floats, frames);
    free(v);
    wethair_sim_destroy(sim);
    return 0;
}
