/* The main job: the paper scene dry and wet side by side (like the paper's figure 6), drawn
 * with Kajiya-Kay shading (METHOD.md eq. 3) by a small software rasteriser with a depth
 * buffer, written to a PNG, plus a ms/frame line. Runs headless: no GPU, no window system.
 *
 * usage: render [--out FILE] [--frames N] [--particles N] [--groom FILE.tfx|.hair] */
#include <string.h>

#include "png.h"
#include "scene.h"

typedef struct { float x, y, z; } V3;
static V3 v3(float x, float y, float z) { V3 r = {x, y, z}; return r; }
static V3 sub(V3 a, V3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static V3 cross(V3 a, V3 b) { return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
static V3 norm(V3 a) { float l = sqrtf(dot(a, a)); return l > 0 ? v3(a.x / l, a.y / l, a.z / l) : a; }

/* A pinhole camera looking at `at` from `eye`, z up. */
typedef struct { V3 eye, fwd, right, up; float focal; int w, h; } Camera;

static Camera camera(V3 eye, V3 at, float fov_deg, int w, int h) {
    Camera c;
    c.eye = eye;
    c.fwd = norm(sub(at, eye));
    c.right = norm(cross(c.fwd, v3(0, 0, 1)));
    c.up = cross(c.right, c.fwd);
    c.focal = 0.5f * (float)h / tanf(0.5f * fov_deg * 3.14159265f / 180.0f);
    c.w = w;
    c.h = h;
    return c;
}

/* Projects p to pixel coordinates and view depth; returns 0 when behind the camera. */
static int project(const Camera *c, V3 p, float *sx, float *sy, float *depth) {
    V3 d = sub(p, c->eye);
    float z = dot(d, c->fwd);
    if (z < 1e-3f) return 0;
    *sx = 0.5f * c->w + c->focal * dot(d, c->right) / z;
    *sy = 0.5f * c->h - c->focal * dot(d, c->up) / z;
    *depth = z;
    return 1;
}

typedef struct { float *rgb, *depth; int w, h; } Target;

static void plot(Target *t, int x, int y, float z, V3 col) {
    if (x < 0 || y < 0 || x >= t->w || y >= t->h) return;
    size_t i = (size_t)y * t->w + x;
    if (z >= t->depth[i]) return;
    t->depth[i] = z;
    t->rgb[3 * i] = col.x;
    t->rgb[3 * i + 1] = col.y;
    t->rgb[3 * i + 2] = col.z;
}

/* Kajiya-Kay (eq. 3) for tangent t, light l, view v; wetness darkens the base colour and
 * sharpens and brightens the highlight (the wet look). */
static V3 kajiya_kay(V3 t, V3 l, V3 v, float wet) {
    float lt = dot(l, t), vt = dot(v, t);
    float sin_l = sqrtf(fmaxf(0.0f, 1.0f - lt * lt)), sin_v = sqrtf(fmaxf(0.0f, 1.0f - vt * vt));
    float shininess = 30.0f + 120.0f * wet;
    float spec = powf(fmaxf(sin_l * sin_v - lt * vt, 0.0f), shininess) * (0.25f + 0.75f * wet);
    float darken = 1.0f - 0.6f * wet;
    V3 base = v3(0.30f * darken, 0.15f * darken, 0.06f * darken);
    float diff = 0.2f + 0.8f * sin_l;
    return v3(base.x * diff + spec, base.y * diff + spec, base.z * diff + spec * 0.95f);
}

/* Draws the segment a-b with per-end tangents and wetness, depth-tested. */
static void draw_segment(Target *t, const Camera *c, V3 a, V3 b, V3 ta, V3 tb, float wa, float wb, V3 light) {
    float ax, ay, az, bx, by, bz;
    if (!project(c, a, &ax, &ay, &az) || !project(c, b, &bx, &by, &bz)) return;
    int n = (int)ceilf(fmaxf(fabsf(bx - ax), fabsf(by - ay))) + 1;
    if (n > 4 * (t->w + t->h)) return; /* degenerate projection */
    for (int k = 0; k <= n; k++) {
        float s = (float)k / (float)n;
        V3 p = v3(a.x + (b.x - a.x) * s, a.y + (b.y - a.y) * s, a.z + (b.z - a.z) * s);
        V3 tan = norm(v3(ta.x + (tb.x - ta.x) * s, ta.y + (tb.y - ta.y) * s, ta.z + (tb.z - ta.z) * s));
        V3 col = kajiya_kay(tan, light, norm(sub(c->eye, p)), wa + (wb - wa) * s);
        int px = (int)(ax + (bx - ax) * s), py = (int)(ay + (by - ay) * s);
        float pz = az + (bz - az) * s;
        plot(t, px, py, pz, col); /* two pixels wide at the supersampled resolution */
        plot(t, px + 1, py, pz, col);
    }
}

/* Ray-casts the head sphere (radius r at the origin) with Lambert shading. */
static void draw_head(Target *t, const Camera *c, float r, V3 light) {
    for (int y = 0; y < t->h; y++) {
        for (int x = 0; x < t->w; x++) {
            V3 dir = norm(v3(c->fwd.x * c->focal + c->right.x * (x - 0.5f * c->w) - c->up.x * (y - 0.5f * c->h),
                             c->fwd.y * c->focal + c->right.y * (x - 0.5f * c->w) - c->up.y * (y - 0.5f * c->h),
                             c->fwd.z * c->focal + c->right.z * (x - 0.5f * c->w) - c->up.z * (y - 0.5f * c->h)));
            float bq = dot(c->eye, dir), cq = dot(c->eye, c->eye) - r * r, disc = bq * bq - cq;
            if (disc < 0) continue;
            float s = -bq - sqrtf(disc);
            V3 p = v3(c->eye.x + dir.x * s, c->eye.y + dir.y * s, c->eye.z + dir.z * s);
            float lam = fmaxf(dot(norm(p), light), 0.0f);
            float z = s * dot(dir, c->fwd);
            plot(t, x, y, z, v3(0.05f + 0.15f * lam, 0.035f + 0.09f * lam, 0.03f + 0.06f * lam));
        }
    }
}

/* Renders one simulation's strands (and its water) into the panel starting at column x0 of the
 * final image, supersampled `ss` times. */
static void render_panel(const WetHairSim *sim, const float *verts, const WetHairVertexLayout *lay, uint8_t *img,
                         int img_w, int x0, int pw, int ph, int ss, int head) {
    Target t = {malloc(sizeof(float) * 3 * (size_t)pw * ss * ph * ss), malloc(sizeof(float) * (size_t)pw * ss * ph * ss),
                pw * ss, ph * ss};
    if (!t.rgb || !t.depth) exit(1);
    for (int i = 0; i < t.w * t.h; i++) {
        float g = 0.10f + 0.08f * (float)(i / t.w) / (float)t.h;
        t.rgb[3 * i] = g;
        t.rgb[3 * i + 1] = g;
        t.rgb[3 * i + 2] = g * 1.15f;
        t.depth[i] = 1e30f;
    }
    Camera cam = camera(v3(0.05f, -0.62f, 0.22f), v3(0.0f, 0.0f, -0.02f), 40.0f, t.w, t.h);
    V3 light = norm(v3(-0.4f, -0.7f, 0.6f));
    if (head) draw_head(&t, &cam, 0.1f, light);
    int stride = (int)lay->stride_floats, po = lay->position_offset / 4, to = lay->tangent_offset / 4,
        wo = lay->wetness_offset / 4;
    /* Strands: consecutive vertices of one strand are joined; strand starts are where the
     * tangent-free rule of pinned roots restarts, i.e. every `points` vertices here. */
    WetHairStats st = wh_stats(sim);
    uint32_t per = st.points / st.strands;
    for (uint32_t s = 0; s < st.strands; s++) {
        for (uint32_t i = 0; i + 1 < per; i++) {
            const float *a = verts + (size_t)(s * per + i) * stride, *b = a + stride;
            draw_segment(&t, &cam, v3(a[po], a[po + 1], a[po + 2]), v3(b[po], b[po + 1], b[po + 2]),
                         v3(a[to], a[to + 1], a[to + 2]), v3(b[to], b[to + 1], b[to + 2]), a[wo], b[wo], light);
        }
    }
    /* Water particles as small bright-blue discs. */
    float water[3 * 4096];
    uint32_t n = 0;
    wh_check(wethair_sim_get_water(sim, water, 4096, &n), "wethair_sim_get_water");
    for (uint32_t j = 0; j < n; j++) {
        float sx, sy, sz;
        if (!project(&cam, v3(water[3 * j], water[3 * j + 1], water[3 * j + 2]), &sx, &sy, &sz)) continue;
        for (int dy = -ss; dy <= ss; dy++)
            for (int dx = -ss; dx <= ss; dx++)
                if (dx * dx + dy * dy <= ss * ss) plot(&t, (int)sx + dx, (int)sy + dy, sz - 1e-3f, v3(0.55f, 0.75f, 1.0f));
    }
    for (int y = 0; y < ph; y++) {
        for (int x = 0; x < pw; x++) {
            for (int ch = 0; ch < 3; ch++) {
                float acc = 0;
                for (int j = 0; j < ss; j++)
                    for (int i = 0; i < ss; i++) acc += t.rgb[3 * ((size_t)(y * ss + j) * t.w + x * ss + i) + ch];
                float v = powf(fminf(fmaxf(acc / (ss * ss), 0.0f), 1.0f), 1.0f / 2.2f);
                img[3 * ((size_t)y * img_w + x0 + x) + ch] = (uint8_t)(v * 255.0f + 0.5f);
            }
        }
    }
    free(t.rgb);
    free(t.depth);
}

int main(int argc, char **argv) {
    const char *out = "wethair.png", *groom_path = NULL;
    uint32_t frames = 200, particles = 1000, backend = WETHAIR_BACKEND_AUTO;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--out")) out = argv[i + 1];
        else if (!strcmp(argv[i], "--frames")) frames = (uint32_t)atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--particles")) particles = (uint32_t)atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--groom")) groom_path = argv[i + 1];
        else if (!strcmp(argv[i], "--backend")) backend = wh_parse_backend(argv[i + 1]);
        else {
            fprintf(stderr, "usage: %s [--out FILE] [--frames N] [--particles N] [--groom FILE] [--backend auto|cpu|gpu]\n",
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
    wethair_groom_destroy(groom);
    wh_print_backend(sims[0]);

    /* The two simulations run one after the other: each has its own worker pool, and an idle
     * pool's threads briefly spin, which would tax the other's timing. */
    uint32_t seed = 12345, per_frame = 50;
    float pos[3 * 50], vel[3 * 50];
    double ms[2] = {0, 0};
    /* Timed: the steps plus one final vertex read, which waits for a GPU to finish them. */
    for (int k = 0; k < 2; k++) {
        WetHairVertexLayout lay = {0};
        lay.struct_size = sizeof lay;
        wh_check(wethair_sim_get_vertex_layout(sims[k], &lay), "wethair_sim_get_vertex_layout");
        size_t cap = (size_t)lay.vertex_count * lay.stride_floats, written = 0;
        float *sync = malloc(cap * sizeof *sync);
        if (!sync) return 1;
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
        WetHairVertexLayout lay = {0};
        lay.struct_size = sizeof lay;
        wh_check(wethair_sim_get_vertex_layout(sims[k], &lay), "wethair_sim_get_vertex_layout");
        size_t cap = (size_t)lay.vertex_count * lay.stride_floats, written = 0;
        float *verts = malloc(cap * sizeof *verts);
        if (!verts) return 1;
        wh_check(wethair_sim_get_vertex_buffer(sims[k], verts, cap, &written), "wethair_sim_get_vertex_buffer");
        render_panel(sims[k], verts, &lay, img, 2 * pw, k * pw, pw, ph, ss, groom_path == NULL);
        free(verts);
        st[k] = wh_stats(sims[k]);
    }
    if (png_write(out, img, 2 * pw, ph)) {
        fprintf(stderr, "could not write %s\n", out);
        return 1;
    }
    printf("wethair %s: %u strands x %u points, %u frames at 1/60 s, 4 substeps, %s\n", wethair_version_string(),
           st[0].strands, st[0].points / st[0].strands, frames,
           st[0].backend == WETHAIR_BACKEND_GPU ? "GPU" : "CPU");
    printf("timing: dry %.3f ms/frame | wet (%u particles sprayed, %u held) %.3f ms/frame\n", ms[0] / frames, particles,
           st[1].particles, ms[1] / frames);
    printf("clumping: dry %.5f m, wet %.5f m (ratio %.3f); wrote %s (dry left, wet right)\n", st[0].clumping,
           st[1].clumping, st[1].clumping / st[0].clumping, out);
    free(img);
    wethair_sim_destroy(sims[0]);
    wethair_sim_destroy(sims[1]);
    return 0;
}
