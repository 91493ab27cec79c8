/* Shared helpers of the C example hosts: error checks, timing, the paper scene with its head
 * collider, and the water shower (the same generator as wethair::scenes::shower). */
#ifndef WETHAIR_EXAMPLE_SCENE_H
#define WETHAIR_EXAMPLE_SCENE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "wethair.h"

/* Exits with the library's message when a call fails. */
static inline void wh_check(WetHairResult r, const char *what) {
    if (r != WETHAIR_OK) {
        fprintf(stderr, "%s failed: %s: %s\n", what, wethair_result_string((uint32_t)r),
                wethair_last_error_message());
        exit(1);
    }
}

/* Milliseconds on a monotonic clock. */
static inline double wh_now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/* Next value in [0, 1) of a 32-bit LCG. */
static inline float wh_rand(uint32_t *state) {
    *state = *state * 1664525u + 1013904223u;
    return (float)(*state >> 8) / (float)(1u << 24);
}

/* `count` particles in a disc of radius 0.16 m at 0.3 m above the head, falling at 1 m/s. */
static inline void wh_shower(uint32_t *state, uint32_t count, float *pos, float *vel) {
    for (uint32_t i = 0; i < count; i++) {
        float r = 0.16f * sqrtf(wh_rand(state));
        float th = wh_rand(state) * 6.28318530718f;
        pos[3 * i + 0] = r * cosf(th);
        pos[3 * i + 1] = r * sinf(th);
        pos[3 * i + 2] = 0.3f;
        vel[3 * i + 0] = 0.0f;
        vel[3 * i + 1] = 0.0f;
        vel[3 * i + 2] = -1.0f;
    }
}

/* A `--backend` value: auto, cpu or gpu; exits on anything else. */
static inline uint32_t wh_parse_backend(const char *s) {
    if (!strcmp(s, "auto")) return WETHAIR_BACKEND_AUTO;
    if (!strcmp(s, "cpu")) return WETHAIR_BACKEND_CPU;
    if (!strcmp(s, "gpu")) return WETHAIR_BACKEND_GPU;
    fprintf(stderr, "--backend must be auto, cpu or gpu, got %s\n", s);
    exit(2);
}

/* "GPU: llvmpipe (...)" or "CPU: 2 threads (AUTO fell back: ...)". */
static inline void wh_print_backend(const WetHairSim *sim) {
    WetHairBackendInfo info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    wh_check(wethair_sim_get_backend_info(sim, &info), "wethair_sim_get_backend_info");
    printf("backend: %s on %s%s%s%s\n", info.backend == WETHAIR_BACKEND_GPU ? "GPU" : "CPU", info.device,
           info.fallback_reason[0] ? " (AUTO chose the CPU: " : "", info.fallback_reason,
           info.fallback_reason[0] ? ")" : "");
}

/* A simulation of `groom` with the default (paper scene) parameters and the head as a sphere
 * collider of radius 0.1 m at the origin, on `backend` (a WetHairBackend). */
static inline WetHairSim *wh_create_paper_sim(const WetHairGroom *groom, uint32_t threads, uint32_t backend) {
    WetHairSimDesc desc;
    wethair_sim_desc_default(&desc);
    WetHairCollider head = {WETHAIR_COLLIDER_SPHERE, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.1f};
    desc.groom = groom;
    desc.colliders = &head;
    desc.collider_count = 1;
    desc.threads = threads;
    desc.backend = backend;
    WetHairSim *sim = NULL;
    wh_check(wethair_sim_create(&desc, &sim), "wethair_sim_create");
    return sim;
}

/* Loads a groom file in metres with the load defaults (1 g per metre of strand, segments
 * under 0.1 mm welded) and says what was welded. */
static inline WetHairGroom *wh_load_groom(const char *path) {
    WetHairLoadDesc load;
    wethair_load_desc_default(&load);
    WetHairGroom *groom = NULL;
    wh_check(wethair_groom_load_with_desc(path, &load, &groom), "wethair_groom_load_with_desc");
    const char *note = wethair_groom_get_load_message(groom);
    if (note && note[0]) printf("%s: %s\n", path, note);
    return groom;
}

/* A simulation of a loaded groom with the current defaults (springs from material
 * properties, the AUTO integrator: right for any sampling), on `backend`. */
static inline WetHairSim *wh_create_groom_sim(const WetHairGroom *groom, uint32_t backend) {
    WetHairSimDesc desc;
    wh_check(wethair_sim_desc_init(&desc, sizeof desc), "wethair_sim_desc_init");
    desc.groom = groom;
    desc.backend = backend;
    WetHairSim *sim = NULL;
    wh_check(wethair_sim_create(&desc, &sim), "wethair_sim_create");
    return sim;
}

/* Reads a simulation's stats (sets struct_size first, as the API asks). */
static inline WetHairStats wh_stats(const WetHairSim *sim) {
    WetHairStats st = {0};
    st.struct_size = sizeof st;
    wh_check(wethair_sim_get_stats(sim, &st), "wethair_sim_get_stats");
    return st;
}

/* A buffer for a simulation's vertices: fills `lay` (struct_size set first, as the API asks)
 * and `cap` (floats), and exits when out of memory. The caller frees it. */
static inline float *wh_vertex_buffer(const WetHairSim *sim, WetHairVertexLayout *lay, size_t *cap) {
    memset(lay, 0, sizeof *lay);
    lay->struct_size = sizeof *lay;
    wh_check(wethair_sim_get_vertex_layout(sim, lay), "wethair_sim_get_vertex_layout");
    *cap = (size_t)lay->vertex_count * lay->stride_floats;
    float *v = malloc(*cap * sizeof *v);
    if (!v) {
        fprintf(stderr, "out of memory for %zu vertex floats\n", *cap);
        exit(1);
    }
    return v;
}

#endif
