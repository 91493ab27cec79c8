/* An interactive viewer: a window where a person turns the head, sprays water where the
 * cursor points, and watches the strands gather into wet bundles. It draws with Vulkan
 * straight from wethair's shared VkBuffer (the simulation runs on the viewer's own VkDevice)
 * where the machine allows it, else with OpenGL 3.3 from the copy path; the choice and its
 * reason are printed at start.
 *
 * usage: viewer [--groom FILE.tfx|.hair | --strands N] [--backend auto|cpu|gpu] [--renderer auto|vulkan|gl]
 *               [--size WxH] [--msaa 1|4] [--validate] [--script FILE] [--screenshot FILE --frames N]
 *               [--wet-model] [--guides N] [--volume] [--sdf-head] [--skinned-roots]
 *               [--fixed-step HZ]
 *
 * Controls: left drag orbit, wheel zoom; space or right mouse: spray at the cursor; arrows turn
 * the head (left/right yaw, up/down pitch), W/A/S/D/Q/E move it; C dry (remove all water);
 * R reset; B switch backend (CPU/GPU); I switch integrator; P pause; N single step; + and -
 * line width; T rain on/off; G gusty wind on/off; K soak the hair (--wet-model); L the simulated
 * fraction of the guides, 100/50/25/10% (--guides); J the scalp's ripple on/off (--skinned-roots);
 * Esc quit. Drawn in the window (and in its title, and on stdout every second):
 * simulation and draw ms/frame, renderer and vertex source, backend and adapter, integrator,
 * points, particles, the clumping measure, the spray rate.
 *
 * --strands N sets the paper scene's strand count (default 10,000; 6 points each) when no groom
 *   file is given: a slower machine, or a software device in the tests, runs a lighter head.
 * --renderer vulkan fails when Vulkan cannot draw; auto (the default) falls back to OpenGL.
 * --msaa N: antialiasing samples (default 4 in a window, 1 in scripted and screenshot runs).
 * --validate (Vulkan) enables VK_LAYER_KHRONOS_validation; any error it reports fails the run.
 * --script FILE replays timed events, one per line: "FRAME COMMAND [ARGS]" with COMMAND one of
 *   spray on|off, yaw DEG, pitch DEG, move DX DY DZ (m), dry, reset, backend cpu|gpu|auto,
 *   integrator symplectic|implicit, pause, resume, step, screenshot FILE (.png or .ppm; the
 *   frame drawn next), resize WxH (the window), stats, rain on|off, wind on|off, soak, quit
 * --wet-model runs the full wet model (held water, liquid bridges, drip, drying in 20 s; on
 *   either backend) and shows the water ledger.
 * --guides N simulates every N-th strand and writes the others as followers (docs/GUIDES.md);
 *   script command "fraction F" sets the simulated fraction. --volume turns hair-hair volume on.
 * --sdf-head collides with the head as a signed distance field (a 44^3 sampled sphere, moved
 *   by the head transform each frame) instead of the analytic sphere.
 * --skinned-roots roots the strands on a skin instead of the rigid head: each frame the host
 *   sets every root's frame (wethair_sim_set_root_frames), the head's turn and offset plus a
 *   ripple that swells the scalp by up to 2 cm as it runs across it; script command
 *   "skin on|off" starts and stops the ripple.
 * --fixed-step HZ advances in fixed steps of 1/HZ s by each frame's time (wethair_sim_advance;
 *   1/60 s a frame when scripted), drawing the vertices blended between the last two steps;
 *   the overlay shows the steps of the last frame and the blend.
 * In script mode the spray aims from the camera at the head, the frame step is a fixed 1/60 s
 * and every frame is stepped (no dropped frames), so runs repeat. */
#include <GLFW/glfw3.h>

#include "font5x7.h"
#include "png.h"
#include "viewer.h"

typedef struct Event {
    int frame;
    char cmd[32];
    char arg[256];
} Event;

void viewer_view_proj(const Viewer *v, float m[16], float eye[3]) {
    float cy = cosf(v->cam_yaw), sy = sinf(v->cam_yaw), cp = cosf(v->cam_pitch), sp = sinf(v->cam_pitch);
    eye[0] = v->target[0] + v->cam_dist * cp * sy;
    eye[1] = v->target[1] - v->cam_dist * cp * cy;
    eye[2] = v->target[2] + v->cam_dist * sp;
    float f[3] = {v->target[0] - eye[0], v->target[1] - eye[1], v->target[2] - eye[2]};
    float l = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int i = 0; i < 3; i++) f[i] /= l;
    float r[3] = {f[1], -f[0], 0.0f};
    l = sqrtf(r[0] * r[0] + r[1] * r[1]);
    r[0] /= l;
    r[1] /= l;
    float u[3] = {r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
    float rows[3][4] = {{r[0], r[1], r[2], 0}, {u[0], u[1], u[2], 0}, {-f[0], -f[1], -f[2], 0}};
    for (int i = 0; i < 3; i++) rows[i][3] = -(rows[i][0] * eye[0] + rows[i][1] * eye[1] + rows[i][2] * eye[2]);
    float t = 1.0f / tanf(0.5f * v->fov), aspect = (float)v->width / (float)v->height;
    float n = 0.01f, fa = 20.0f, a = (fa + n) / (n - fa), b = 2.0f * fa * n / (n - fa);
    for (int c = 0; c < 4; c++) {
        m[4 * c + 0] = t / aspect * rows[0][c];
        m[4 * c + 1] = t * rows[1][c];
        m[4 * c + 2] = a * rows[2][c] + (c == 3 ? b : 0.0f);
        m[4 * c + 3] = -rows[2][c];
    }
}

int viewer_text_scale(const Viewer *v) { return v->width >= 800 ? 2 : 1; }

size_t viewer_text_triangles(const Viewer *v, float **buf, size_t *cap) {
    const int scale = viewer_text_scale(v), x0 = 8, y0 = 8;
    size_t n = 0;
    for (int line = 0; line < OVERLAY_LINES; line++)
        for (const char *c = v->overlay[line]; *c; c++) n += 35 * 12;
    if (n > *cap) {
        free(*buf);
        *cap = n;
        *buf = malloc(n * sizeof(float));
        if (!*buf) exit(1);
    }
    size_t k = 0;
    float sx = 2.0f / (float)v->width, sy = 2.0f / (float)v->height;
    for (int line = 0; line < OVERLAY_LINES; line++) {
        int col = 0;
        for (const char *c = v->overlay[line]; *c; c++, col++) {
            const uint8_t *g = font5x7_glyph(*c);
            if (!g) continue;
            for (int r = 0; r < 7; r++)
                for (int b = 0; b < 5; b++) {
                    if (!(g[r] >> (4 - b) & 1)) continue;
                    float x = (float)(x0 + (col * 6 + b) * scale), y = (float)(y0 + (line * 10 + r) * scale);
                    float l = x * sx - 1.0f, t = 1.0f - y * sy, rr = (x + scale) * sx - 1.0f, bb = 1.0f - (y + scale) * sy;
                    float q[12] = {l, t, rr, t, rr, bb, l, t, rr, bb, l, bb};
                    memcpy(*buf + k, q, sizeof q);
                    k += 12;
                }
        }
    }
    return k;
}

uint32_t *viewer_line_indices(const WetHairVertexLayout *lay, uint32_t *n) {
    uint32_t per = lay->vertex_count / lay->strand_count;
    *n = lay->strand_count * (per - 1) * 2;
    uint32_t *ix = malloc(sizeof(uint32_t) * (size_t)*n);
    if (!ix) exit(1);
    for (uint32_t s = 0, k = 0; s < lay->strand_count; s++)
        for (uint32_t i = 0; i + 1 < per; i++) {
            ix[k++] = s * per + i;
            ix[k++] = s * per + i + 1;
        }
    return ix;
}

/* The head transform: yaw about z, then pitch about x, then the offset; column-major. */
static void head_matrix(const Viewer *v, float m[16]) {
    float cy = cosf(v->head_yaw), sy = sinf(v->head_yaw), cp = cosf(v->head_pitch), sp = sinf(v->head_pitch);
    float r[9] = {cy, sy, 0, -sy * cp, cy * cp, sp, sy * sp, -cy * sp, cp}; /* columns */
    memset(m, 0, 16 * sizeof(float));
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) m[4 * c + k] = r[3 * c + k];
    m[12] = v->head_pos[0];
    m[13] = v->head_pos[1];
    m[14] = v->head_pos[2];
    m[15] = 1.0f;
}

static const char *integrator_name(uint32_t i) {
    return i == WETHAIR_INTEGRATOR_IMPLICIT_EULER ? "implicit Euler" : "symplectic Euler";
}

/* (Re)creates the simulation with the current backend and integrator; reuses the groom. */
/* Applies the rain and wind toggles to the simulation (rain over the head, falling at 4 m/s;
 * a 3 m/s wind along x with gusts). */
static void set_weather(Viewer *v) {
    WetHairRain rain = {{0.0f, 0.0f, 0.45f}, {0.4f, 0.4f}, 600.0f, 4.0f, 7};
    wh_check(wethair_sim_set_rain(v->sim, v->raining ? &rain : NULL), "wethair_sim_set_rain");
    WetHairWind wind = {{v->windy ? 3.0f : 0.0f, 0.0f, 0.0f}, v->windy ? 0.5f : 0.0f, 1};
    wh_check(wethair_sim_set_wind(v->sim, &wind), "wethair_sim_set_wind");
}

/* Sets the simulated fraction of the guides (--guides only; says so otherwise). */
static void set_fraction(Viewer *v, float f) {
    if (!v->guides) {
        printf("viewer: a guide fraction needs --guides N\n");
        return;
    }
    v->guide_fraction = f;
    wh_check(wethair_sim_set_guide_fraction(v->sim, f), "wethair_sim_set_guide_fraction");
    printf("viewer: simulating %.0f%% of the guides\n", 100.0 * f);
}

/* The skinned roots' frames for this frame (--skinned-roots): each rest root (head space)
 * pushed out from the roots' centre by a ripple that runs along x, 2 cm at its crest, 1.5
 * times a second; then the head's turn and offset. Every root turns with the head. */
static void set_root_frames(Viewer *v) {
    if (!v->skinned || !v->rest_roots) return;
    float m[16];
    head_matrix(v, m);
    uint32_t n = v->root_count;
    const float *c = v->root_center;
    float *pos = v->root_frames, *rot = v->root_frames + 3 * (size_t)n;
    /* The head's turn as a quaternion: yaw about z, then pitch about x (as head_matrix). */
    float hy = 0.5f * v->head_yaw, hp = 0.5f * v->head_pitch;
    float q[4] = {sinf(hp) * cosf(hy), sinf(hp) * sinf(hy), cosf(hp) * sinf(hy), cosf(hp) * cosf(hy)};
    for (uint32_t k = 0; k < n; k++) {
        const float *r = v->rest_roots + 3 * (size_t)k;
        float d[3] = {r[0] - c[0], r[1] - c[1], r[2] - c[2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        float swell = 0.02f * (0.5f + 0.5f * sinf(2.0f * 3.14159265f * 1.5f * v->skin_time - 40.0f * r[0]));
        float p[3];
        for (int a = 0; a < 3; a++) p[a] = r[a] + (len > 0.0f ? swell * d[a] / len : 0.0f);
        for (int a = 0; a < 3; a++) pos[3 * k + a] = m[a] * p[0] + m[4 + a] * p[1] + m[8 + a] * p[2] + m[12 + a];
        memcpy(rot + 4 * (size_t)k, q, sizeof q);
    }
    wh_check(wethair_sim_set_root_frames(v->sim, pos, rot, n), "wethair_sim_set_root_frames");
}

/* Reads the roots' rest positions in head space (--skinned-roots): the first vertex of each
 * strand of a simulation just reset, taken back through the head transform. */
static void read_rest_roots(Viewer *v) {
    size_t cap = (size_t)v->lay.vertex_count * v->lay.stride_floats, written = 0;
    float *buf = malloc(sizeof(float) * cap), m[16];
    v->root_count = v->lay.strand_count;
    v->rest_roots = malloc(sizeof(float) * 3 * (size_t)v->root_count);
    v->root_frames = malloc(sizeof(float) * 7 * (size_t)v->root_count);
    if (!buf || !v->rest_roots || !v->root_frames) exit(1);
    wh_check(wethair_sim_get_vertex_buffer(v->sim, buf, cap, &written), "wethair_sim_get_vertex_buffer");
    head_matrix(v, m);
    uint32_t per = v->lay.vertex_count / v->lay.strand_count;
    for (uint32_t k = 0; k < v->root_count; k++) {
        const float *p = buf + (size_t)k * per * v->lay.stride_floats;
        float d[3] = {p[0] - m[12], p[1] - m[13], p[2] - m[14]};
        for (int a = 0; a < 3; a++) /* the transpose of the head's turn */
            v->rest_roots[3 * k + a] = m[4 * a] * d[0] + m[4 * a + 1] * d[1] + m[4 * a + 2] * d[2];
    }
    for (uint32_t k = 0; k < v->root_count; k++)
        for (int a = 0; a < 3; a++) v->root_center[a] += v->rest_roots[3 * k + a] / (float)v->root_count;
    free(buf);
}

/* Soaks the hair (the wet model only; says so otherwise). */
static void soak(Viewer *v) {
    /* Twice what the hair holds, as out of a bath: the excess runs down and drips. */
    if (v->wet_model) wh_check(wethair_sim_soak(v->sim, 2.0f), "wethair_sim_soak");
    else printf("viewer: soak needs --wet-model\n");
}

static void make_sim(Viewer *v) {
    if (v->sim) wethair_sim_destroy(v->sim);
    /* The paper scene runs the paper's exact parameters; a groom file the current defaults
     * (springs from material properties, right for any sampling). */
    WetHairSimDesc desc;
    /* The 0.1.0 layout has neither the wet model, nor guides, nor the volume. */
    int current = v->wet_model || v->guides || v->volume || v->sdf_head || v->skinned || v->fixed_hz > 0.0f;
    if (v->is_paper && !current) wethair_sim_desc_default(&desc);
    else wh_check(wethair_sim_desc_init(&desc, sizeof desc), "wethair_sim_desc_init");
    if (v->is_paper && current) {
        desc.spring_model = WETHAIR_SPRING_MODEL_PER_SPRING; /* the paper's springs, current layout */
        desc.integrator = WETHAIR_INTEGRATOR_SYMPLECTIC_EULER;
    }
    if (v->is_paper && v->wet_model) {
        /* 1 g points (wisps of thousands of hairs): a thirtieth of the capacity, a fiftieth of
         * the water between fibres, 30 mg drops. */
        desc.held_water.capacity_ratio = 0.01f;
        desc.held_water_free_ratio = 0.02f;
        desc.held_water.drip_mass = 3.0e-5f;
    }
    if (v->wet_model) {
        desc.held_water.enabled = 1;
        desc.held_water.dry_time = 20.0f; /* 60x faster than in air, to watch it dry */
    }
    WetHairCollider head = {WETHAIR_COLLIDER_SPHERE, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.1f};
    desc.groom = v->groom;
    if (v->is_paper) {
        desc.colliders = &head;
        desc.collider_count = 1;
    }
    if (v->guides > 0) {
        desc.guides.choice = WETHAIR_GUIDES_EVERY_NTH;
        desc.guides.count = v->guides;
        desc.guides.fraction = v->guide_fraction;
    }
    if (v->volume) desc.volume.enabled = 1;
    if (v->fixed_hz > 0.0f) desc.fixed_step = 1.0f / v->fixed_hz;
    desc.skinned_roots = (uint32_t)v->skinned;
    /* The SDF head: distances to a 0.1 m sphere every 5 mm, two cells of margin. */
    static float sdf_values[44 * 44 * 44];
    WetHairSdf sdf;
    memset(&sdf, 0, sizeof sdf);
    if (v->sdf_head && v->is_paper) {
        const float cell = 0.005f, half = 0.11f;
        for (int k = 0; k < 44; k++)
            for (int j = 0; j < 44; j++)
                for (int i = 0; i < 44; i++) {
                    float x = -half + cell * i, y = -half + cell * j, z = -half + cell * k;
                    sdf_values[(k * 44 + j) * 44 + i] = sqrtf(x * x + y * y + z * z) - 0.1f;
                }
        for (int a = 0; a < 3; a++) {
            sdf.dims[a] = 44;
            sdf.origin[a] = -half;
        }
        sdf.cell_size = cell;
        sdf.values = sdf_values;
        head_matrix(v, sdf.transform);
        desc.sdfs = &sdf;
        desc.sdf_count = 1;
        desc.collider_count = 0;
    }
    desc.backend = v->backend;
    desc.integrator = v->integrator;
    desc.readback = WETHAIR_READBACK_LATEST;
    desc.water.capacity = MAX_PARTICLES;
    v->sim = NULL;
    WetHairResult r = v->r.create_sim(v, &desc, &v->sim);
    if (r != WETHAIR_OK && v->backend != WETHAIR_BACKEND_CPU) {
        fprintf(stderr, "viewer: GPU backend unavailable (%s); using the CPU\n", wethair_last_error_message());
        v->backend = WETHAIR_BACKEND_CPU;
        desc.backend = v->backend;
        r = v->r.create_sim(v, &desc, &v->sim);
    }
    wh_check(r, "wethair_sim_create");
    float m[16];
    head_matrix(v, m);
    wh_check(wethair_sim_set_head_transform(v->sim, m), "wethair_sim_set_head_transform");
    wh_check(wethair_sim_reset(v->sim), "wethair_sim_reset");
    set_weather(v);
    wh_print_backend(v->sim);
    printf("viewer: integrator %s; strands drawn with %s from the %s\n", integrator_name(v->integrator), v->api,
           v->r.source(v));
}

/* A cone of particles from the camera towards (dx, dy) in normalised device coordinates. */
static void spray(Viewer *v, float ndc_x, float ndc_y, uint32_t count) {
    float m[16], eye[3];
    viewer_view_proj(v, m, eye);
    float cy = cosf(v->cam_yaw), sy = sinf(v->cam_yaw), cp = cosf(v->cam_pitch), sp = sinf(v->cam_pitch);
    float f[3] = {-cp * sy, cp * cy, -sp}; /* towards the target */
    float r[3] = {f[1], -f[0], 0.0f}, rl = sqrtf(r[0] * r[0] + r[1] * r[1]);
    r[0] /= rl;
    r[1] /= rl;
    float u[3] = {r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
    float t = tanf(0.5f * v->fov), aspect = (float)v->width / (float)v->height;
    float pos[3 * 64], vel[3 * 64];
    if (count > 64) count = 64;
    for (uint32_t i = 0; i < count; i++) {
        float jx = ndc_x + 0.04f * (wh_rand(&v->seed) - 0.5f), jy = ndc_y + 0.04f * (wh_rand(&v->seed) - 0.5f);
        float d[3];
        for (int k = 0; k < 3; k++) d[k] = f[k] + jx * t * aspect * r[k] + jy * t * u[k];
        /* Start just outside the hair (the water domain ends a strand's length out). */
        float dl = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), start = fmaxf(0.0f, v->cam_dist - 0.35f);
        for (int k = 0; k < 3; k++) {
            d[k] /= dl;
            pos[3 * i + k] = eye[k] + start * d[k];
            vel[3 * i + k] = 2.0f * d[k];
        }
    }
    WetHairResult res = wethair_sim_add_water(v->sim, pos, vel, count);
    if (res == WETHAIR_ERROR_CAPACITY) return; /* full: the shower pauses until particles leave */
    wh_check(res, "wethair_sim_add_water");
}

/* Draws a frame; when `path` is set, also writes it (PNG, or PPM by extension). */
static void draw_frame(Viewer *v, const char *path) {
    if (!path) {
        v->r.draw(v, NULL);
        return;
    }
    size_t n = (size_t)v->width * v->height * 3;
    uint8_t *rgb = malloc(n);
    if (!rgb) exit(1);
    v->r.draw(v, rgb);
    size_t len = strlen(path);
    int fail;
    if (len > 4 && !strcmp(path + len - 4, ".ppm")) {
        FILE *f = fopen(path, "wb");
        fail = !f;
        if (f) {
            fprintf(f, "P6\n%d %d\n255\n", v->width, v->height);
            fail = fwrite(rgb, 1, n, f) != n;
            fclose(f);
        }
    } else {
        fail = png_write(path, rgb, v->width, v->height);
    }
    free(rgb);
    if (fail) {
        fprintf(stderr, "could not write %s\n", path);
        exit(1);
    }
    WetHairStats st = wh_stats(v->sim);
    printf("viewer: screenshot %s: clumping %.5f m, %u particles\n", path, st.clumping, st.particles);
}

static void print_stats(Viewer *v) {
    WetHairStats st = wh_stats(v->sim);
    WetHairBackendInfo info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    wh_check(wethair_sim_get_backend_info(v->sim, &info), "wethair_sim_get_backend_info");
    int n = v->frames_in_window ? v->frames_in_window : 1;
    const char *be = info.backend == WETHAIR_BACKEND_GPU ? "GPU" : "CPU";
    char title[512];
    snprintf(title, sizeof title,
             "wethair | sim %.2f ms  draw %.2f ms | %s from the %s | %s %s | %s | %u points, %u particles | "
             "clumping %.4f m%s",
             v->sim_ms / n, v->draw_ms / n, v->api, v->r.source(v), be, info.device, integrator_name(v->integrator),
             st.points, st.particles, st.clumping, v->paused ? " | paused" : "");
    glfwSetWindowTitle(v->window, title);
    printf("%s\n", title);
    snprintf(v->overlay[0], sizeof v->overlay[0], "SIM %.2f MS  DRAW %.2f MS  %s FROM THE %s", v->sim_ms / n,
             v->draw_ms / n, v->api, v->r.source(v));
    snprintf(v->overlay[1], sizeof v->overlay[1], "%s %s  %s  %u POINTS  %u PARTICLES  CLUMPING %.2f MM", be,
             info.device, integrator_name(v->integrator), st.points, st.particles, 1e3 * st.clumping);
    char fixed[96] = "";
    if (v->fixed_hz > 0.0f) {
        snprintf(fixed, sizeof fixed, "  FIXED STEP 1/%g S: %u STEPS, BLEND %.2f", v->fixed_hz, v->advance.steps,
                 v->advance.blend);
        printf("fixed step 1/%g s: last frame %u steps, blend %.3f\n", v->fixed_hz, v->advance.steps,
               v->advance.blend);
    }
    snprintf(v->overlay[2], sizeof v->overlay[2], "SPRAY %d PARTICLES/S (SPACE, RIGHT MOUSE)  LINES %.1f PX%s%s%s",
             SPRAY_PER_FRAME * 60, v->line_width, v->paused ? "  PAUSED" : "",
             !v->skinned ? "" : v->skin_moving ? "  SKINNED ROOTS: RIPPLE (J)" : "  SKINNED ROOTS: STILL (J)", fixed);
    if (v->wet_model) {
        double g = WETHAIR_WATER_QUANTUM_KG * 1e3;
        snprintf(v->overlay[3], sizeof v->overlay[3],
                 "RAIN %s (T)  WIND %s (G)  WATER G: ADDED %.1f = DROPS %.1f + HELD %.1f + LEFT %.1f + DRIED %.1f",
                 v->raining ? "ON" : "OFF", v->windy ? "ON" : "OFF", g * (double)st.water_added,
                 g * (double)st.water_in_particles, g * (double)st.water_held, g * (double)st.water_left,
                 g * (double)st.water_evaporated);
        printf("water: added %llu = particles %llu + held %llu + left %llu + evaporated %llu quanta\n",
               (unsigned long long)st.water_added, (unsigned long long)st.water_in_particles,
               (unsigned long long)st.water_held, (unsigned long long)st.water_left,
               (unsigned long long)st.water_evaporated);
    } else {
        snprintf(v->overlay[3], sizeof v->overlay[3], "RAIN %s (T)  WIND %s (G)  (--WET-MODEL: HELD WATER)",
                 v->raining ? "ON" : "OFF", v->windy ? "ON" : "OFF");
    }
    v->sim_ms = v->draw_ms = 0.0;
    v->frames_in_window = 0;
}

/* Runs a script event; a screenshot is returned (taken of the frame drawn next). */
static const char *run_event(Viewer *v, const Event *e) {
    if (!strcmp(e->cmd, "spray")) v->spraying = !strcmp(e->arg, "on");
    else if (!strcmp(e->cmd, "yaw")) v->head_yaw = (float)atof(e->arg) * 3.14159265f / 180.0f;
    else if (!strcmp(e->cmd, "pitch")) v->head_pitch = (float)atof(e->arg) * 3.14159265f / 180.0f;
    else if (!strcmp(e->cmd, "move")) sscanf(e->arg, "%f %f %f", &v->head_pos[0], &v->head_pos[1], &v->head_pos[2]);
    else if (!strcmp(e->cmd, "dry")) wh_check(wethair_sim_clear_water(v->sim), "wethair_sim_clear_water");
    else if (!strcmp(e->cmd, "fraction")) set_fraction(v, (float)atof(e->arg));
    else if (!strcmp(e->cmd, "reset")) wh_check(wethair_sim_reset(v->sim), "wethair_sim_reset");
    else if (!strcmp(e->cmd, "backend")) {
        v->backend = wh_parse_backend(e->arg);
        make_sim(v);
    } else if (!strcmp(e->cmd, "integrator")) {
        v->integrator = !strcmp(e->arg, "implicit") ? WETHAIR_INTEGRATOR_IMPLICIT_EULER : WETHAIR_INTEGRATOR_SYMPLECTIC_EULER;
        make_sim(v);
    } else if (!strcmp(e->cmd, "rain") || !strcmp(e->cmd, "wind")) {
        *(!strcmp(e->cmd, "rain") ? &v->raining : &v->windy) = !strcmp(e->arg, "on");
        set_weather(v);
    } else if (!strcmp(e->cmd, "soak")) soak(v);
    else if (!strcmp(e->cmd, "pause")) v->paused = 1;
    else if (!strcmp(e->cmd, "resume")) v->paused = 0;
    else if (!strcmp(e->cmd, "step")) v->step_once = 1;
    else if (!strcmp(e->cmd, "screenshot")) return e->arg;
    else if (!strcmp(e->cmd, "stats")) print_stats(v);
    else if (!strcmp(e->cmd, "resize")) {
        int w = 0, h = 0;
        if (sscanf(e->arg, "%dx%d", &w, &h) == 2 && w > 0 && h > 0) glfwSetWindowSize(v->window, w, h);
    }
    else if (!strcmp(e->cmd, "quit")) glfwSetWindowShouldClose(v->window, 1);
    else {
        fprintf(stderr, "script: unknown command %s\n", e->cmd);
        exit(2);
    }
    return NULL;
}

static void load_script(Viewer *v, const char *path) {
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "cannot read %s\n", path);
        exit(2);
    }
    char line[512];
    while (fgets(line, sizeof line, f)) {
        Event e = {0};
        int used = 0;
        if (line[0] == '#' || sscanf(line, "%d %31s %n", &e.frame, e.cmd, &used) < 2) continue;
        snprintf(e.arg, sizeof e.arg, "%s", line + used);
        e.arg[strcspn(e.arg, "\r\n")] = 0;
        Event *grown = realloc(v->events, sizeof(Event) * (size_t)(v->n_events + 1));
        if (!grown) exit(1);
        v->events = grown;
        v->events[v->n_events++] = e;
    }
    fclose(f);
    v->scripted = 1;
}

static void on_key(GLFWwindow *win, int key, int scancode, int action, int mods) {
    (void)scancode;
    (void)mods;
    Viewer *v = glfwGetWindowUserPointer(win);
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    switch (key) {
    case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(win, 1); break;
    case GLFW_KEY_C: wh_check(wethair_sim_clear_water(v->sim), "wethair_sim_clear_water"); break;
    case GLFW_KEY_R: wh_check(wethair_sim_reset(v->sim), "wethair_sim_reset"); break;
    case GLFW_KEY_P: v->paused = !v->paused; break;
    case GLFW_KEY_T:
        v->raining = !v->raining;
        set_weather(v);
        break;
    case GLFW_KEY_G:
        v->windy = !v->windy;
        set_weather(v);
        break;
    case GLFW_KEY_K: soak(v); break;
    case GLFW_KEY_J: v->skin_moving = !v->skin_moving; break;
    case GLFW_KEY_L: {
        /* 100% -> 50% -> 25% -> 10% -> 100% */
        float f = v->guide_fraction;
        set_fraction(v, f > 0.75f ? 0.5f : f > 0.4f ? 0.25f : f > 0.2f ? 0.1f : 1.0f);
        break;
    }
    case GLFW_KEY_N: v->step_once = 1; break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: v->line_width = fminf(8.0f, v->line_width + 0.5f); break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: v->line_width = fmaxf(1.0f, v->line_width - 0.5f); break;
    case GLFW_KEY_B: {
        /* From the backend running now (AUTO may have chosen either). */
        WetHairBackendInfo info;
        memset(&info, 0, sizeof info);
        info.struct_size = sizeof info;
        wh_check(wethair_sim_get_backend_info(v->sim, &info), "wethair_sim_get_backend_info");
        v->backend = info.backend == WETHAIR_BACKEND_CPU ? WETHAIR_BACKEND_GPU : WETHAIR_BACKEND_CPU;
        make_sim(v);
        break;
    }
    case GLFW_KEY_I:
        v->integrator = v->integrator == WETHAIR_INTEGRATOR_IMPLICIT_EULER ? WETHAIR_INTEGRATOR_SYMPLECTIC_EULER
                                                                           : WETHAIR_INTEGRATOR_IMPLICIT_EULER;
        make_sim(v);
        break;
    default: break;
    }
}

static void on_scroll(GLFWwindow *win, double dx, double dy) {
    (void)dx;
    Viewer *v = glfwGetWindowUserPointer(win);
    v->cam_dist *= powf(0.9f, (float)dy);
}

/* Camera and target fitted to the groom's bounds (from its rest vertices). */
static void fit_camera(Viewer *v) {
    size_t cap = (size_t)v->lay.vertex_count * v->lay.stride_floats, written = 0;
    float *verts = malloc(cap * sizeof(float));
    if (!verts) exit(1);
    wh_check(wethair_sim_get_vertex_buffer(v->sim, verts, cap, &written), "wethair_sim_get_vertex_buffer");
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    int po = v->lay.position_offset / 4;
    for (uint32_t i = 0; i < v->lay.vertex_count; i++)
        for (int k = 0; k < 3; k++) {
            float x = verts[(size_t)i * v->lay.stride_floats + po + k];
            lo[k] = fminf(lo[k], x);
            hi[k] = fmaxf(hi[k], x);
        }
    free(verts);
    float radius = 0.0f;
    for (int k = 0; k < 3; k++) {
        v->target[k] = 0.5f * (lo[k] + hi[k]);
        radius = fmaxf(radius, 0.5f * (hi[k] - lo[k]));
    }
    v->target[2] -= 0.3f * radius; /* room for the hair to fall */
    v->cam_dist = 1.4f * radius / tanf(0.5f * v->fov);
}

/* Reads the held keys and the mouse: orbit, head motion, spray. */
static void poll_input(Viewer *v) {
    GLFWwindow *win = v->window;
    double mx, my;
    glfwGetCursorPos(win, &mx, &my);
    int left = glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (left && v->dragging) {
        v->cam_yaw -= 0.005f * (float)(mx - v->last_x);
        v->cam_pitch = fminf(1.4f, fmaxf(-1.4f, v->cam_pitch + 0.005f * (float)(my - v->last_y)));
    }
    v->dragging = left;
    v->last_x = mx;
    v->last_y = my;
    float step_rad = 0.03f, step_m = 0.005f;
    if (glfwGetKey(win, GLFW_KEY_LEFT) == GLFW_PRESS) v->head_yaw += step_rad;
    if (glfwGetKey(win, GLFW_KEY_RIGHT) == GLFW_PRESS) v->head_yaw -= step_rad;
    if (glfwGetKey(win, GLFW_KEY_UP) == GLFW_PRESS) v->head_pitch += step_rad;
    if (glfwGetKey(win, GLFW_KEY_DOWN) == GLFW_PRESS) v->head_pitch -= step_rad;
    if (glfwGetKey(win, GLFW_KEY_W) == GLFW_PRESS) v->head_pos[1] += step_m;
    if (glfwGetKey(win, GLFW_KEY_S) == GLFW_PRESS) v->head_pos[1] -= step_m;
    if (glfwGetKey(win, GLFW_KEY_A) == GLFW_PRESS) v->head_pos[0] -= step_m;
    if (glfwGetKey(win, GLFW_KEY_D) == GLFW_PRESS) v->head_pos[0] += step_m;
    if (glfwGetKey(win, GLFW_KEY_Q) == GLFW_PRESS) v->head_pos[2] += step_m;
    if (glfwGetKey(win, GLFW_KEY_E) == GLFW_PRESS) v->head_pos[2] -= step_m;
    int spray_now = v->spraying || glfwGetKey(win, GLFW_KEY_SPACE) == GLFW_PRESS ||
                    glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    if (spray_now) {
        float nx = v->scripted ? 0.0f : (float)(2.0 * mx / v->width - 1.0);
        float ny = v->scripted ? 0.0f : (float)(1.0 - 2.0 * my / v->height);
        spray(v, nx, ny, SPRAY_PER_FRAME);
    }
}

int main(int argc, char **argv) {
    Viewer v;
    memset(&v, 0, sizeof v);
    v.width = 1280;
    v.height = 720;
    v.backend = WETHAIR_BACKEND_AUTO;
    v.integrator = WETHAIR_INTEGRATOR_SYMPLECTIC_EULER;
    v.seed = 2024;
    v.fov = 40.0f * 3.14159265f / 180.0f;
    v.cam_pitch = 0.25f;
    v.line_width = 1.0f;
    v.guide_fraction = 1.0f;
    const char *groom_path = NULL, *shot = NULL, *script = NULL, *renderer = "auto";
    int frames = 0, msaa = 0;
    uint32_t paper_strands = 10000;
    for (int i = 1; i < argc; i++) {
        if (i + 1 < argc && !strcmp(argv[i], "--groom")) groom_path = argv[++i];
        else if (i + 1 < argc && !strcmp(argv[i], "--strands")) {
            char *end = NULL;
            long n = strtol(argv[++i], &end, 10);
            if (end == argv[i] || *end != '\0' || n < 1 || n > 1000000) {
                fprintf(stderr, "viewer: --strands wants a strand count from 1 to 1000000\n");
                return 2;
            }
            paper_strands = (uint32_t)n;
        }
        else if (!strcmp(argv[i], "--wet-model")) v.wet_model = 1;
        else if (i + 1 < argc && !strcmp(argv[i], "--guides")) v.guides = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--volume")) v.volume = 1;
        else if (!strcmp(argv[i], "--sdf-head")) v.sdf_head = 1;
        else if (!strcmp(argv[i], "--skinned-roots")) v.skinned = v.skin_moving = 1;
        else if (i + 1 < argc && !strcmp(argv[i], "--fixed-step")) {
            v.fixed_hz = (float)atof(argv[++i]);
            if (!(v.fixed_hz >= 1.0f)) {
                fprintf(stderr, "viewer: --fixed-step wants steps per second, 1 or more\n");
                return 2;
            }
        }
        else if (i + 1 < argc && !strcmp(argv[i], "--backend")) v.backend = wh_parse_backend(argv[++i]);
        else if (i + 1 < argc && !strcmp(argv[i], "--renderer")) renderer = argv[++i];
        else if (i + 1 < argc && !strcmp(argv[i], "--script")) script = argv[++i];
        else if (i + 1 < argc && !strcmp(argv[i], "--screenshot")) shot = argv[++i];
        else if (i + 1 < argc && !strcmp(argv[i], "--frames")) frames = atoi(argv[++i]);
        else if (i + 1 < argc && !strcmp(argv[i], "--size")) sscanf(argv[++i], "%dx%d", &v.width, &v.height);
        else if (i + 1 < argc && !strcmp(argv[i], "--msaa")) msaa = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--validate")) v.validate = 1;
        else {
            fprintf(stderr,
                    "usage: %s [--groom FILE | --strands N] [--backend auto|cpu|gpu] [--renderer auto|vulkan|gl] [--size WxH] "
                    "[--msaa 1|4] [--validate] [--script FILE] [--screenshot FILE --frames N] [--wet-model] "
                    "[--guides N] [--volume] [--sdf-head] [--skinned-roots] [--fixed-step HZ]\n",
                    argv[0]);
            return 2;
        }
    }
    int want_vk = !strcmp(renderer, "auto") || !strcmp(renderer, "vulkan"), want_gl = strcmp(renderer, "vulkan") != 0;
    if (!want_vk && strcmp(renderer, "gl") != 0) {
        fprintf(stderr, "viewer: unknown renderer %s (auto, vulkan, gl)\n", renderer);
        return 2;
    }
    if (script) load_script(&v, script);
    if (shot && frames <= 0) frames = 120;
    /* Antialiasing where it is cheap: a person's window, not the scripted software runs. */
    v.samples = msaa > 0 ? msaa : script || shot ? 1 : 4;
    if (!glfwInit()) {
        fprintf(stderr, "viewer: GLFW could not start (no display? try xvfb-run)\n");
        return 1;
    }
    char why[512] = "not asked for";
    int opened = want_vk && vk_renderer_open(&v, why, sizeof why);
    if (!opened && want_vk) printf("viewer: Vulkan renderer unavailable: %s\n", why);
    if (!opened && want_gl) {
        opened = gl_renderer_open(&v, why, sizeof why);
        if (!opened) fprintf(stderr, "viewer: OpenGL renderer unavailable: %s\n", why);
    }
    if (!opened) {
        glfwTerminate();
        return 1;
    }
    /* One line pixel per screen point: wider on high-density displays. */
    float csx = 1.0f, csy = 1.0f;
    glfwGetWindowContentScale(v.window, &csx, &csy);
    v.line_width = fmaxf(1.0f, csx);
    glfwSetWindowUserPointer(v.window, &v);
    glfwSetKeyCallback(v.window, on_key);
    glfwSetScrollCallback(v.window, on_scroll);

    if (groom_path) {
        v.groom = wh_load_groom(groom_path);
        /* Real grooms' short, light segments are too stiff for symplectic Euler at 60 Hz. */
        v.integrator = WETHAIR_INTEGRATOR_IMPLICIT_EULER;
    }
    else wh_check(wethair_groom_create_paper_scene(paper_strands, 6, &v.groom), "wethair_groom_create_paper_scene");
    v.is_paper = groom_path == NULL;
    make_sim(&v);
    v.lay.struct_size = sizeof v.lay;
    wh_check(wethair_sim_get_vertex_layout(v.sim, &v.lay), "wethair_sim_get_vertex_layout");
    if (v.skinned) read_rest_roots(&v);
    fit_camera(&v);
    snprintf(v.overlay[0], sizeof v.overlay[0], "WETHAIR %s", wethair_version_string());

    int frame = 0;
    double last_print = wh_now_ms();
    while (!glfwWindowShouldClose(v.window)) {
        glfwPollEvents();
        const char *shot_now = NULL;
        while (v.next_event < v.n_events && v.events[v.next_event].frame <= frame) {
            const char *s = run_event(&v, &v.events[v.next_event++]);
            if (s) shot_now = s;
        }
        if (glfwWindowShouldClose(v.window)) break;
        poll_input(&v);
        float hm[16];
        head_matrix(&v, hm);
        wh_check(wethair_sim_set_head_transform(v.sim, hm), "wethair_sim_set_head_transform");
        if (v.sdf_head && v.is_paper) wh_check(wethair_sim_set_sdf_transform(v.sim, 0, hm), "wethair_sim_set_sdf_transform");

        double t0 = wh_now_ms();
        /* A person's frame lasts what it lasted (the fixed steps take it in whole steps, and
         * wethair cuts a stall to desc.max_frame_time); a scripted or single-stepped one
         * 1/60 s, so runs repeat. */
        float frame_s = 1.0f / 60.0f;
        if (v.fixed_hz > 0.0f && !v.scripted && !shot && !v.step_once && v.last_frame_ms > 0.0)
            frame_s = (float)((t0 - v.last_frame_ms) * 1e-3);
        v.last_frame_ms = t0;
        if (!v.paused || v.step_once) {
            if (v.skin_moving) v.skin_time += frame_s;
            set_root_frames(&v);
            if (v.fixed_hz > 0.0f) {
                v.advance.struct_size = sizeof v.advance;
                wh_check(wethair_sim_advance(v.sim, frame_s, &v.advance), "wethair_sim_advance");
            } else {
                wh_check(wethair_sim_step(v.sim, frame_s), "wethair_sim_step");
            }
            v.step_once = 0;
        }
        double t1 = wh_now_ms();
        frame++;
        if (shot && frame == frames) shot_now = shot;
        draw_frame(&v, shot_now);
        double t2 = wh_now_ms();
        v.sim_ms += t1 - t0;
        v.draw_ms += t2 - t1;
        v.frames_in_window++;
        if (shot && frame == frames) glfwSetWindowShouldClose(v.window, 1);
        if (wh_now_ms() - last_print > 1000.0) {
            print_stats(&v);
            last_print = wh_now_ms();
        }
    }
    if (v.frames_in_window) print_stats(&v);
    free(v.events);
    free(v.rest_roots);
    free(v.root_frames);
    wethair_sim_destroy(v.sim);
    wethair_groom_destroy(v.groom);
    v.r.close(&v);
    glfwTerminate();
    return 0;
}
