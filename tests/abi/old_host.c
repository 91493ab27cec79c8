/* A host compiled against the saved 0.1.0 header (tests/abi/wethair-0.1.0.h), linked to this
 * library: every sized struct passes its 0.1.0 size, and everything must still work; sizes
 * outside the accepted range are refused with WETHAIR_ERROR_STRUCT_SIZE and nothing written.
 * Build: cc -Itests/abi tests/abi/old_host.c -Ltarget/release -lwethair ... */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "wethair-0.1.0.h"

static int failures = 0;
#define CHECK(cond, ...)                                                      \
    do {                                                                      \
        if (!(cond)) {                                                        \
            fprintf(stderr, "old_host: FAILED %s: ", #cond);                  \
            fprintf(stderr, __VA_ARGS__);                                     \
            fprintf(stderr, " (%s)\n", wethair_last_error_message());        \
            failures++;                                                       \
        }                                                                     \
    } while (0)

int main(void) {
    WetHairGroom *groom = NULL;
    CHECK(wethair_groom_create_paper_scene(64, 6, &groom) == WETHAIR_OK, "paper scene");

    /* The groom desc from the host's own arrays. */
    float pos[] = {0, 0, 0, 0, 0, -0.02f, 0, 0, -0.04f};
    uint32_t counts[] = {3};
    WetHairGroomDesc gd;
    wethair_groom_desc_default(&gd);
    CHECK(gd.struct_size == sizeof gd, "groom desc default wrote size %u", gd.struct_size);
    gd.strand_count = 1; gd.strand_point_counts = counts; gd.positions = pos; gd.point_count = 3;
    WetHairGroom *own = NULL;
    CHECK(wethair_groom_create(&gd, &own) == WETHAIR_OK, "groom from arrays");

    WetHairSimDesc desc;
    wethair_sim_desc_default(&desc);
    CHECK(desc.struct_size == sizeof desc, "sim desc default wrote size %u", desc.struct_size);
    desc.groom = groom;
    desc.backend = WETHAIR_BACKEND_CPU;
    WetHairSim *sim = NULL;
    CHECK(wethair_sim_create(&desc, &sim) == WETHAIR_OK, "sim create with the 0.1.0 desc");
    if (!sim) return 1;

    float water[3 * 50];
    for (int i = 0; i < 50; i++) { water[3 * i] = 0.01f * (i % 7); water[3 * i + 1] = 0.01f * (i % 5); water[3 * i + 2] = 0.15f; }
    CHECK(wethair_sim_add_water(sim, water, NULL, 50) == WETHAIR_OK, "add water");
    for (int f = 0; f < 10; f++) CHECK(wethair_sim_step(sim, 1.0f / 60.0f) == WETHAIR_OK, "step %d", f);

    WetHairVertexLayout layout;
    memset(&layout, 0, sizeof layout);
    layout.struct_size = sizeof layout;
    CHECK(wethair_sim_get_vertex_layout(sim, &layout) == WETHAIR_OK, "layout");
    CHECK(layout.struct_size == sizeof layout && layout.vertex_count == 64 * 6 && layout.stride_floats == 7,
          "layout %u %u %u", layout.struct_size, layout.vertex_count, layout.stride_floats);
    size_t cap = (size_t)layout.vertex_count * layout.stride_floats, written = 0;
    float *v = malloc(cap * sizeof(float));
    CHECK(wethair_sim_get_vertex_buffer(sim, v, cap, &written) == WETHAIR_OK && written == cap, "vertices");
    free(v);

    WetHairStats st;
    memset(&st, 0, sizeof st);
    st.struct_size = sizeof st;
    CHECK(wethair_sim_get_stats(sim, &st) == WETHAIR_OK, "stats");
    CHECK(st.struct_size == sizeof st && st.steps == 10 && st.strands == 64 && st.backend == WETHAIR_BACKEND_CPU,
          "stats %u %llu %u", st.struct_size, (unsigned long long)st.steps, st.strands);

    WetHairBackendInfo info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    CHECK(wethair_sim_get_backend_info(sim, &info) == WETHAIR_OK && info.backend == WETHAIR_BACKEND_CPU, "backend info");

    WetHairVulkanInstanceRequirements req;
    memset(&req, 0, sizeof req);
    req.struct_size = sizeof req;
    WetHairResult r = wethair_vulkan_get_instance_requirements(&req);
    CHECK(r == WETHAIR_OK || r == WETHAIR_ERROR_UNSUPPORTED, "instance requirements %u", r);

    /* Sizes outside the accepted range: refused, nothing written. */
    WetHairStats bad;
    memset(&bad, 0x5a, sizeof bad);
    bad.struct_size = sizeof bad + 4096; /* a newer header than this library */
    CHECK(wethair_sim_get_stats(sim, &bad) == WETHAIR_ERROR_STRUCT_SIZE, "larger stats accepted");
    CHECK(bad.strands == 0x5a5a5a5au, "written on failure");
    bad.struct_size = 4; /* smaller than any released layout */
    CHECK(wethair_sim_get_stats(sim, &bad) == WETHAIR_ERROR_STRUCT_SIZE, "tiny stats accepted");
    WetHairSimDesc big = desc;
    big.struct_size = sizeof big + 4096; /* larger than any layout this library will have */
    WetHairSim *none = (WetHairSim *)0x1;
    CHECK(wethair_sim_create(&big, &none) == WETHAIR_ERROR_STRUCT_SIZE && none == (WetHairSim *)0x1, "larger desc");

    wethair_sim_destroy(sim);
    wethair_groom_destroy(own);
    wethair_groom_destroy(groom);
    if (failures) return 1;
    printf("old_host: a host built against the 0.1.0 header works with wethair %s\n", wethair_version_string());
    return 0;
}
