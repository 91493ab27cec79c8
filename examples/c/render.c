/* The main job: the paper scene's groom over time under the full wet model (a strip: dry,
 * soaked, dripping, half dry, dry again; docs/WET_MODEL.md), and the paper's own model dry and
 * wet side by side (like the paper's figure 6), drawn by the software rasteriser in raster.h,
 * written to PNGs, plus ms/frame lines. Runs headless: no GPU, no window system.
 *
 * usage: render [--out FILE] [--frames N] [--particles N] [--groom FILE.tfx|.hair]
 *               [--backend auto|cpu|gpu] [--strip-seconds S]
 * writes FILE (the strip; S = 0 leaves it out) and FILE less ".png" plus "-paper.png" (the pair). */
#include <string.h>

#include "png.h"
#include "raster.h"
#include "scene.h"

/* Reads a simulation's vertices and renders them into the panel at column x0. */
static void draw_sim(WetHairSim *sim, uint8_t *img, int img_w, int x0, int pw, int ph, int ss, int head) {
    WetHairVertexLayout lay;
    size_t cap, written = 0;
    float *verts = wh_vertex_buffer(sim, &lay, &cap);
    wh_check(wethair_sim_get_vertex_buffer(sim, verts, cap, &written), "wethair_sim_get_vertex_buffer");
    render_panel(sim, verts, &lay, img, img_w, x0, pw, ph, ss, head);
    free(verts);
}

/* Grams of water in `quanta`. */
static double grams(uint64_t quanta) { return (double)quanta * WETHAIR_WATER_QUANTUM_KG * 1e3; }

/* The strip: a simulation with held water (drying sped up to a time constant of 1 s so that a
 * few seconds show what takes half an hour in air) and a dry twin, stepped together for
 * `seconds`. At 0.5 s the host soaks the hair past its hold limit (wethair_sim_soak, as after
 * a dunk) and showers it with `particles` drops; panels are drawn dry (just before), soaked
 * (1.0 s), dripping (1.5 s), half dry (when the hair holds half its peak) and dry again (the
 * end). */
static int run_strip(const char *out, const WetHairGroom *groom, uint32_t backend, float seconds, uint32_t particles) {
    /* The current layout (it has held_water) with the paper scene's springs and integrator. */
    WetHairSimDesc desc;
    wh_check(wethair_sim_desc_init(&desc, sizeof desc), "wethair_sim_desc_init");
    desc.spring_model = WETHAIR_SPRING_MODEL_PER_SPRING;
    desc.integrator = WETHAIR_INTEGRATOR_SYMPLECTIC_EULER;
    WetHairCollider head = {WETHAIR_COLLIDER_SPHERE, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.1f};
    desc.groom = groom;
    desc.colliders = &head;
    desc.collider_count = 1;
    desc.backend = backend;
    WetHairSim *dry = NULL, *wet = NULL;
    wh_check(wethair_sim_create(&desc, &dry), "wethair_sim_create");
    /* The paper scene's points weigh 1 g each (a wisp of some 8,000 hairs; 50 kg of hair in
     * all): at the default 1.3 kg of water per kg (0.3 in the fibres, 1 between them) it would
     * hold 65 kg and shed tens of thousands of drops. A thirtieth of the capacity and a fiftieth
     * of the water between fibres hold about 2 kg, and what passes that is shed as 30 mg
     * (3.9 mm) drops. */
    desc.held_water.enabled = 1;
    desc.held_water.dry_time = 1.0f;
    desc.held_water.capacity_ratio = 0.01f;
    desc.held_water_free_ratio = 0.02f;
    desc.held_water.drip_mass = 3.0e-5f;
    wh_check(wethair_sim_create(&desc, &wet), "wethair_sim_create");
    /* A frame is timed as its step and its vertex read: on the GPU backend a step only
     * submits, and the read is what waits for the device. */
    WetHairVertexLayout lay;
    size_t cap, written = 0;
    float *verts = wh_vertex_buffer(wet, &lay, &cap);

    enum { PANELS = 5 };
    static const char *names[PANELS] = {"dry", "soaked", "dripping", "half dry", "dry again"};
    const int pw = 400, ph = 400, ss = 3;
    uint8_t *img = calloc((size_t)PANELS * pw * ph * 3, 1);
    if (!img) return 1;
    const float dt = 1.0f / 60.0f, soak_at = 0.5f;
    const uint32_t frames = (uint32_t)lroundf(seconds / dt), per_frame = 50;
    uint32_t seed = 12345, added = 0, soaked = 0;
    int panel = 0;
    double ms = 0, peak = 0;
    float pos[3 * 50], vel[3 * 50];
    char line[PANELS][96] = {{0}};
    for (uint32_t f = 1; f <= frames && panel < PANELS; f++) {
        float t = (float)f * dt;
        if (t > soak_at) {
            if (!soaked) {
                /* Half as much again as the hair holds, as out of a bath: the excess runs and drips. */
                wh_check(wethair_sim_soak(wet, 1.5f), "wethair_sim_soak");
                soaked = 1;
            }
            if (added < particles) {
                uint32_t n = particles - added < per_frame ? particles - added : per_frame;
                wh_shower(&seed, n, pos, vel);
                wh_check(wethair_sim_add_water(wet, pos, vel, n), "wethair_sim_add_water");
                added += n;
            }
        }
        double t0 = wh_now_ms();
        wh_check(wethair_sim_step(wet, dt), "wethair_sim_step");
        wh_check(wethair_sim_get_vertex_buffer(wet, verts, cap, &written), "wethair_sim_get_vertex_buffer");
        ms += wh_now_ms() - t0;
        wh_check(wethair_sim_step(dry, dt), "wethair_sim_step");
        /* The stats measure clumping (a nearest-tip search): read them every tenth of a second. */
        float at[PANELS - 1] = {soak_at, 1.0f, 1.5f, 0.0f};
        int fixed = panel < PANELS - 2 && fabsf(t - at[panel]) < 0.5f * dt;
        if (!fixed && f != frames && f % 6 != 0) continue;
        WetHairStats sw = wh_stats(wet), sd = wh_stats(dry);
        double held = grams(sw.water_held);
        if (held > peak) peak = held;
        int half = panel == PANELS - 2 && t > 1.5f && held <= 0.5 * peak;
        if (!fixed && f != frames && !half) continue;
        const char *name = names[panel];
        if (f == frames && !fixed && !half && panel < PANELS - 1) {
            panel = PANELS - 1; /* a run cut short ends in the last panel, named for what it is */
            name = "end";
        }
        draw_sim(wet, img, PANELS * pw, panel * pw, pw, ph, ss, 1);
        snprintf(line[panel], sizeof line[panel], "%.1f S %s", t, name);
        draw_label(img, PANELS * pw, ph, panel * pw + 12, 12, (panel + 1) * pw, 3, line[panel]);
        snprintf(line[panel], sizeof line[panel], "%s %.2f s: held %.0f g, %u drops, clumping %.2f of dry", name,
                 t, held, sw.particles, sw.clumping / sd.clumping);
        panel++;
    }
    if (png_write(out, img, PANELS * pw, ph)) {
        fprintf(stderr, "could not write %s\n", out);
        return 1;
    }
    WetHairStats sw = wh_stats(wet);
    printf("wet model (held water, bridges, flow, drip, drying 1200x faster than in air): %.3f ms/frame (a step and "
           "a vertex read) on %s; wrote %s\n",
           ms / frames, sw.backend == WETHAIR_BACKEND_GPU ? "GPU" : "CPU", out);
    for (int k = 0; k < panel; k++)
        if (line[k][0]) printf("  %s\n", line[k]);
    printf("  water: added %.1f g = particles %.1f + held %.1f + left %.1f + evaporated %.1f\n", grams(sw.water_added),
           grams(sw.water_in_particles), grams(sw.water_held), grams(sw.water_left), grams(sw.water_evaporated));
    free(img);
    free(verts);
    wethair_sim_destroy(wet);
    wethair_sim_destroy(dry);
    /* Water is counted in whole quanta: the ledger balances exactly, or something is wrong. */
    if (sw.water_added != sw.water_in_particles + sw.water_held + sw.water_left + sw.water_evaporated) {
        fprintf(stderr, "the water ledger does not balance\n");
        return 1;
    }
    return 0;
}

int main(int argc, char **argv) {
    const char *out = "wethair.png", *groom_path = NULL;
    uint32_t frames = 200, particles = 1000, backend = WETHAIR_BACKEND_AUTO;
    float strip_seconds = 10.0f;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--out")) out = argv[i + 1];
        else if (!strcmp(argv[i], "--frames")) frames = (uint32_t)atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--particles")) particles = (uint32_t)atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--groom")) groom_path = argv[i + 1];
        else if (!strcmp(argv[i], "--backend")) backend = wh_parse_backend(argv[i + 1]);
        else if (!strcmp(argv[i], "--strip-seconds")) strip_seconds = (float)atof(argv[i + 1]);
        else {
            fprintf(stderr,
                    "usage: %s [--out FILE] [--frames N] [--particles N] [--groom FILE] [--backend auto|cpu|gpu] "
                    "[--strip-seconds S]\n",
                    argv[0]);
            return 2;
        }
    }
    WetHairGroom *groom = NULL;
    WetHairSim *sims[2];
    if (groom_path) {
        groom = wh_load_groom(groom_path);
        for (int k = 0; k < 2; k++) sims[k] = wh_create_groom_sim(groom, backend);
    } else {
        wh_check(wethair_groom_create_paper_scene(10000, 6, &groom), "wethair_groom_create_paper_scene");
        for (int k = 0; k < 2; k++) sims[k] = wh_create_paper_sim(groom, 0, backend);
    }
    wh_print_backend(sims[0]);
    /* The pair goes beside the strip: FILE.png -> FILE-paper.png. */
    char pair[1024];
    size_t stem = strlen(out) > 4 && !strcmp(out + strlen(out) - 4, ".png") ? strlen(out) - 4 : strlen(out);
    if (stem + 11 > sizeof pair) return 2;
    memcpy(pair, out, stem);
    strcpy(pair + stem, "-paper.png");

    /* The two simulations run one after the other: each has its own worker pool, and an idle
     * pool's threads briefly spin, which would tax the other's timing. */
    uint32_t seed = 12345, per_frame = 50;
    float pos[3 * 50], vel[3 * 50];
    double ms[2] = {0, 0};
    /* Timed: the steps plus one final vertex read, which waits for a GPU to finish them. */
    for (int k = 0; k < 2; k++) {
        WetHairVertexLayout lay;
        size_t cap, written = 0;
        float *sync = wh_vertex_buffer(sims[k], &lay, &cap);
        uint32_t added = 0;
        for (uint32_t f = 0; f < frames; f++) {
            if (k == 1 && added < particles) {
                uint32_t n = particles - added < per_frame ? particles - added : per_frame;
                wh_shower(&seed, n, pos, vel);
                wh_check(wethair_sim_add_water(sims[1], pos, vel, n), "wethair_sim_add_water");
                added += n;
            }
            double t0 = wh_now_ms();
            wh_check(wethair_sim_step(sims[k], 1.0f / 60.0f), "wethair_sim_step");
            ms[k] += wh_now_ms() - t0;
        }
        double t0 = wh_now_ms();
        wh_check(wethair_sim_get_vertex_buffer(sims[k], sync, cap, &written), "wethair_sim_get_vertex_buffer");
        ms[k] += wh_now_ms() - t0;
        free(sync);
    }
    const int pw = 640, ph = 640, ss = 3;
    uint8_t *img = calloc((size_t)2 * pw * ph * 3, 1);
    if (!img) return 1;
    WetHairStats st[2];
    for (int k = 0; k < 2; k++) {
        draw_sim(sims[k], img, 2 * pw, k * pw, pw, ph, ss, groom_path == NULL);
        st[k] = wh_stats(sims[k]);
    }
    if (png_write(pair, img, 2 * pw, ph)) {
        fprintf(stderr, "could not write %s\n", pair);
        return 1;
    }
    printf("wethair %s: %u strands x %u points, %u frames at 1/60 s, 4 substeps, %s\n", wethair_version_string(),
           st[0].strands, st[0].points / st[0].strands, frames,
           st[0].backend == WETHAIR_BACKEND_GPU ? "GPU" : "CPU");
    printf("timing (paper model): dry %.3f ms/frame | wet (%u particles sprayed, %u held) %.3f ms/frame\n", ms[0] / frames, particles,
           st[1].particles, ms[1] / frames);
    printf("clumping: dry %.5f m, wet %.5f m (ratio %.3f); wrote %s (dry left, wet right)\n", st[0].clumping,
           st[1].clumping, st[1].clumping / st[0].clumping, pair);
    free(img);
    wethair_sim_destroy(sims[0]);
    wethair_sim_destroy(sims[1]);
    if (groom_path) {
        wethair_groom_destroy(groom);
        wh_check(wethair_groom_create_paper_scene(10000, 6, &groom), "wethair_groom_create_paper_scene");
    }
    int rc = strip_seconds > 0 ? run_strip(out, groom, backend, strip_seconds, particles) : 0;
    wethair_groom_destroy(groom);
    return rc;
}
