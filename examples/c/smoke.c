/* Smoke test of the C ABI: the paper scene dry and under a shower of 1,000 water particles,
 * 200 frames each; reads the vertex buffer every frame and fails on any error or non-finite
 * value; prints dry and wet clumping and the timing. Exit status 0 only when wet hair clumps
 * (and fixed steps, skinned roots and colliders on bones do as documented).
 *
 * usage: smoke [FRAMES [STRANDS]] [--backend auto|cpu|gpu] [--lose-device]
 * --lose-device instead checks the device-loss path: after a few frames the GPU device is made
 * to fail; the next calls must return WETHAIR_ERROR_DEVICE without writing anything, and the
 * host then cleans up and exits 0. */
#include <string.h>

#include "scene.h"

/* The device-loss path (see the usage above). */
static int lose_device(WetHairSim *dry, WetHairSim *wet) {
    for (int f = 0; f < 3; f++) wh_check(wethair_sim_step(wet, 1.0f / 60.0f), "wethair_sim_step");
    wh_check(wethair_sim_debug_lose_device(wet), "wethair_sim_debug_lose_device");
    WetHairResult r = wethair_sim_step(wet, 1.0f / 60.0f);
    float verts[64] = {0};
    size_t written = 12345;
    WetHairResult r2 = wethair_sim_get_vertex_buffer(wet, verts, 64, &written);
    /* The water's read back too: an error, never an empty list that reads as "no water". */
    uint32_t held = 777;
    WetHairResult r3 = wethair_sim_get_water(wet, verts, 21, &held);
    int ok = r == WETHAIR_ERROR_DEVICE && (r2 == WETHAIR_ERROR_DEVICE || r2 == WETHAIR_ERROR_BUFFER_TOO_SMALL) &&
             written == 12345 && verts[0] == 0.0f && r3 == WETHAIR_ERROR_DEVICE && held == 777;
    printf("after device loss: step -> %s (%s)\n", wethair_result_string((uint32_t)r), wethair_last_error_message());
    wethair_sim_destroy(wet);
    wethair_sim_destroy(dry);
    if (!ok) {
        fprintf(stderr, "device loss was not reported as WETHAIR_ERROR_DEVICE\n");
        return 1;
    }
    printf("smoke: device loss handled\n");
    return 0;
}

/* Fixed steps (wethair_sim_advance): a 144 Hz host takes 120 steps of 1/120 s a second, the
 * vertices stay finite, and a frame too short for a step still moves them (the blend between
 * the last two steps advances). Returns 0 when all holds. */
static int fixed_steps(uint32_t backend) {
    WetHairGroom *groom = NULL;
    wh_check(wethair_groom_create_paper_scene(200, 6, &groom), "wethair_groom_create_paper_scene");
    WetHairSimDesc desc;
    wh_check(wethair_sim_desc_init(&desc, sizeof desc), "wethair_sim_desc_init");
    desc.groom = groom;
    desc.backend = backend;
    desc.fixed_step = 1.0f / 120.0f;
    WetHairSim *sim = NULL;
    wh_check(wethair_sim_create(&desc, &sim), "wethair_sim_create (fixed steps)");
    wethair_groom_destroy(groom);
    WetHairVertexLayout layout;
    size_t cap, written = 0;
    float *a = wh_vertex_buffer(sim, &layout, &cap), *b = malloc(cap * sizeof *b);
    if (!b) return 1;
    uint32_t steps = 0;
    int ok = 1;
    for (int f = 0; f < 144; f++) {
        WetHairAdvance adv = {0};
        adv.struct_size = sizeof adv;
        wh_check(wethair_sim_advance(sim, 1.0f / 144.0f, &adv), "wethair_sim_advance");
        steps += adv.steps;
        wh_check(wethair_sim_get_vertex_buffer(sim, a, cap, &written), "wethair_sim_get_vertex_buffer");
        for (size_t i = 0; i < written; i++) ok &= isfinite(a[i]) != 0;
    }
    wh_check(wethair_sim_advance(sim, 0.003f, NULL), "wethair_sim_advance (no step)");
    wh_check(wethair_sim_get_vertex_buffer(sim, b, cap, &written), "wethair_sim_get_vertex_buffer");
    int moved = memcmp(a, b, cap * sizeof *a) != 0;
    printf("fixed steps: %u steps in 144 frames of 1/144 s; a frame without a step moved the vertices: %s\n", steps,
           moved ? "yes" : "no");
    free(a);
    free(b);
    wethair_sim_destroy(sim);
    return ok && moved && steps == 120 ? 0 : 1;
}

/* Skinned roots (wethair_sim_set_root_frames): every root of a 50-strand groom raised 5 cm
 * and turned a quarter turn about z; after one step each root vertex sits on its frame. A
 * short count is refused. Returns 0 when all holds. */
static int skinned_roots(uint32_t backend) {
    enum { STRANDS = 50, POINTS = 6 };
    WetHairGroom *groom = NULL;
    wh_check(wethair_groom_create_paper_scene(STRANDS, POINTS, &groom), "wethair_groom_create_paper_scene");
    WetHairSimDesc desc;
    wh_check(wethair_sim_desc_init(&desc, sizeof desc), "wethair_sim_desc_init");
    desc.groom = groom;
    desc.backend = backend;
    desc.skinned_roots = 1;
    WetHairSim *sim = NULL;
    wh_check(wethair_sim_create(&desc, &sim), "wethair_sim_create (skinned roots)");
    wethair_groom_destroy(groom);
    WetHairVertexLayout layout;
    size_t cap, written = 0;
    float *v = wh_vertex_buffer(sim, &layout, &cap);
    float pos[STRANDS * 3], rot[STRANDS * 4];
    /* The rest pose's roots: the first vertex of each strand. */
    wh_check(wethair_sim_get_vertex_buffer(sim, v, cap, &written), "wethair_sim_get_vertex_buffer");
    const float s = 0.70710678f;
    for (int k = 0; k < STRANDS; k++) {
        const float *r = v + (size_t)k * POINTS * layout.stride_floats;
        pos[3 * k + 0] = -r[1];
        pos[3 * k + 1] = r[0];
        pos[3 * k + 2] = r[2] + 0.05f;
        rot[4 * k + 0] = 0.0f;
        rot[4 * k + 1] = 0.0f;
        rot[4 * k + 2] = s;
        rot[4 * k + 3] = s;
    }
    wh_check(wethair_sim_set_root_frames(sim, pos, rot, STRANDS), "wethair_sim_set_root_frames");
    wh_check(wethair_sim_step(sim, 1.0f / 60.0f), "wethair_sim_step");
    wh_check(wethair_sim_get_vertex_buffer(sim, v, cap, &written), "wethair_sim_get_vertex_buffer");
    float worst = 0.0f;
    for (int k = 0; k < STRANDS; k++) {
        const float *r = v + (size_t)k * POINTS * layout.stride_floats;
        for (int c = 0; c < 3; c++) worst = fmaxf(worst, fabsf(r[c] - pos[3 * k + c]));
    }
    int refused = wethair_sim_set_root_frames(sim, pos, rot, STRANDS - 1) == WETHAIR_ERROR_INVALID_ARGUMENT;
    printf("skinned roots: roots within %.2g m of their frames; a short count refused: %s\n", worst,
           refused ? "yes" : "no");
    free(v);
    wethair_sim_destroy(sim);
    return worst < 1e-6f && refused ? 0 : 1;
}

/* Colliders on bones (WetHairSimDesc::collider_frames, wethair_sim_set_collider_transform): a
 * capsule 0.5 m long and 3 cm in radius, in a frame of its own, rises 0.35 m into the paper
 * scene's hair over 60 frames while the head stays still; after each step no free vertex is
 * inside it, and at the end hair rests on it. A mirrored frame is refused, and a simulation
 * whose colliders follow the head refuses a frame. Returns 0 when all holds. */
static int collider_frames(uint32_t backend) {
    enum { STRANDS = 300, POINTS = 6, FRAMES = 90 };
    WetHairGroom *groom = NULL;
    wh_check(wethair_groom_create_paper_scene(STRANDS, POINTS, &groom), "wethair_groom_create_paper_scene");
    WetHairSimDesc desc;
    wh_check(wethair_sim_desc_init(&desc, sizeof desc), "wethair_sim_desc_init");
    desc.groom = groom;
    desc.backend = backend;
    WetHairCollider bar = {WETHAIR_COLLIDER_CAPSULE, {-0.25f, 0.0f, 0.0f}, {0.25f, 0.0f, 0.0f}, 0.03f};
    float frame[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -0.4f, 1};
    desc.colliders = &bar;
    desc.collider_count = 1;
    desc.collider_frames = frame;
    WetHairSim *sim = NULL;
    wh_check(wethair_sim_create(&desc, &sim), "wethair_sim_create (collider frames)");
    WetHairVertexLayout layout;
    size_t cap, written = 0;
    float *v = wh_vertex_buffer(sim, &layout, &cap);
    float worst = 0.0f;
    int resting = 0;
    for (int f = 1; f <= FRAMES; f++) {
        frame[14] = -0.4f + 0.35f * fminf(1.0f, (float)f / 60.0f);
        wh_check(wethair_sim_set_collider_transform(sim, 0, frame), "wethair_sim_set_collider_transform");
        wh_check(wethair_sim_step(sim, 1.0f / 60.0f), "wethair_sim_step");
        wh_check(wethair_sim_get_vertex_buffer(sim, v, cap, &written), "wethair_sim_get_vertex_buffer");
        resting = 0;
        for (size_t k = 0; k < (size_t)STRANDS * POINTS; k++) {
            if (k % POINTS == 0) continue; /* roots, pinned to the head */
            const float *p = v + k * layout.stride_floats;
            float over = fmaxf(fabsf(p[0]) - 0.25f, 0.0f), dz = p[2] - frame[14];
            float d = sqrtf(over * over + p[1] * p[1] + dz * dz);
            worst = fmaxf(worst, 0.03f - d);
            resting += d < 0.032f;
        }
    }
    float mirrored[16];
    memcpy(mirrored, frame, sizeof mirrored);
    mirrored[0] = -1.0f;
    int refused = wethair_sim_set_collider_transform(sim, 0, mirrored) == WETHAIR_ERROR_INVALID_ARGUMENT;
    free(v);
    wethair_sim_destroy(sim);
    desc.collider_frames = NULL;
    wh_check(wethair_sim_create(&desc, &sim), "wethair_sim_create (colliders on the head)");
    refused &= wethair_sim_set_collider_transform(sim, 0, frame) == WETHAIR_ERROR_UNSUPPORTED;
    wethair_sim_destroy(sim);
    wethair_groom_destroy(groom);
    printf("collider frames: a raised capsule holds %d vertices on it, none deeper than %.2g m; refusals: %s\n",
           resting, fmaxf(worst, 0.0f), refused ? "yes" : "no");
    return worst < 1e-5f && resting > 20 && refused ? 0 : 1;
}

int main(int argc, char **argv) {
    uint32_t frames = 200, strands = 10000, backend = WETHAIR_BACKEND_AUTO, positional = 0;
    int lose = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--backend") && i + 1 < argc) backend = wh_parse_backend(argv[++i]);
        else if (!strcmp(argv[i], "--lose-device")) lose = 1;
        else if (positional++ == 0) frames = (uint32_t)atoi(argv[i]);
        else strands = (uint32_t)atoi(argv[i]);
    }
    const uint32_t particles = 1000, per_frame = 50;
    if (wethair_version() != WETHAIR_VERSION) {
        fprintf(stderr, "header %s does not match library %s\n", WETHAIR_VERSION_STRING, wethair_version_string());
        return 1;
    }
    WetHairGroom *groom = NULL;
    wh_check(wethair_groom_create_paper_scene(strands, 6, &groom), "wethair_groom_create_paper_scene");
    WetHairSim *dry = wh_create_paper_sim(groom, 0, backend);
    WetHairSim *wet = wh_create_paper_sim(groom, 0, backend);
    wethair_groom_destroy(groom); /* the simulations keep their own copy */
    wh_print_backend(wet);
    if (lose) return lose_device(dry, wet);

    WetHairVertexLayout layout;
    size_t cap;
    float *verts = wh_vertex_buffer(wet, &layout, &cap);
    float *pos = malloc(3 * per_frame * sizeof *pos), *vel = malloc(3 * per_frame * sizeof *vel);
    if (!pos || !vel) return 1;

    /* Dry first, then wet: each simulation has its own worker pool, and running them one
     * after the other keeps one pool's idle spinning out of the other's timing. A frame is
     * timed as its step and its vertex read, for both: on the GPU backend a step only
     * submits, and the read is what waits for the device (timing the steps alone counted the
     * wet frames' GPU work in the untimed reads, 0.4 ms a frame on lavapipe against 57 dry). */
    uint32_t seed = 12345, added = 0;
    double dry_ms = 0, wet_ms = 0;
    size_t written = 0;
    for (uint32_t f = 0; f < frames; f++) {
        double t0 = wh_now_ms();
        wh_check(wethair_sim_step(dry, 1.0f / 60.0f), "wethair_sim_step (dry)");
        wh_check(wethair_sim_get_vertex_buffer(dry, verts, cap, &written), "wethair_sim_get_vertex_buffer (dry)");
        dry_ms += wh_now_ms() - t0;
    }
    for (uint32_t f = 0; f < frames; f++) {
        if (added < particles) {
            wh_shower(&seed, per_frame, pos, vel);
            wh_check(wethair_sim_add_water(wet, pos, vel, per_frame), "wethair_sim_add_water");
            added += per_frame;
        }
        double t1 = wh_now_ms();
        wh_check(wethair_sim_step(wet, 1.0f / 60.0f), "wethair_sim_step (wet)");
        wh_check(wethair_sim_get_vertex_buffer(wet, verts, cap, &written), "wethair_sim_get_vertex_buffer");
        wet_ms += wh_now_ms() - t1;
        if (written != cap) {
            fprintf(stderr, "wrote %zu floats, expected %zu\n", written, cap);
            return 1;
        }
        for (size_t i = 0; i < written; i++) {
            if (!isfinite(verts[i])) {
                fprintf(stderr, "frame %u: non-finite vertex value at %zu\n", f, i);
                return 1;
            }
        }
    }
    WetHairStats sd = wh_stats(dry), sw = wh_stats(wet);
    /* The counters alone (cheap enough for every frame): the stats' counters, no measures. */
    WetHairStats cw = {0};
    cw.struct_size = sizeof cw;
    wh_check(wethair_sim_get_counters(wet, &cw), "wethair_sim_get_counters");
    if (cw.particles != sw.particles || cw.steps != sw.steps || cw.clumping != -1.0f || cw.clumping_along != -1.0f) {
        fprintf(stderr, "counters differ from the stats' counters\n");
        return 1;
    }
    printf("smoke: %u strands x 6 points, %u frames, %u threads\n", sd.strands, frames, sd.threads);
    printf("clumping (mean tip-to-nearest-tip, m): dry %.5f  wet %.5f  ratio %.3f  (%u particles held, %llu ran off)\n",
           sd.clumping, sw.clumping, sw.clumping / sd.clumping, sw.particles, (unsigned long long)sw.particles_removed);
    printf("timing (a step and a vertex read): dry %.3f ms/frame, wet %.3f ms/frame\n", dry_ms / frames,
           wet_ms / frames);

    /* The error path: a NaN time step is refused with a message, and nothing changes. */
    if (wethair_sim_step(wet, NAN) != WETHAIR_ERROR_INVALID_ARGUMENT || strlen(wethair_last_error_message()) == 0) {
        fprintf(stderr, "NaN dt was not refused\n");
        return 1;
    }
    int ok = sw.clumping < 0.9f * sd.clumping;
    if (fixed_steps(backend) != 0) {
        fprintf(stderr, "fixed steps failed\n");
        return 1;
    }
    if (skinned_roots(backend) != 0) {
        fprintf(stderr, "skinned roots failed\n");
        return 1;
    }
    if (collider_frames(backend) != 0) {
        fprintf(stderr, "collider frames failed\n");
        return 1;
    }
    free(verts);
    free(pos);
    free(vel);
    wethair_sim_destroy(dry);
    wethair_sim_destroy(wet);
    if (!ok) {
        fprintf(stderr, "wet hair did not clump\n");
        return 1;
    }
    printf("smoke: OK\n");
    return 0;
}
