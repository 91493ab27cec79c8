/* The main job's software rasteriser: a pinhole camera, Kajiya-Kay shaded strands (METHOD.md
 * eq. 3) with a depth buffer, the head as a ray-cast sphere, water particles as discs and a
 * 5x7 label, rendered supersampled into one panel of a larger RGB image. Headless: no GPU, no
 * window system. */
#ifndef WETHAIR_EXAMPLE_RASTER_H
#define WETHAIR_EXAMPLE_RASTER_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "font5x7.h"
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

/* Writes `text` in 5x7 glyphs `scale` pixels per dot, light grey, with its top-left corner at
 * (x, y) of an RGB image `img_w` pixels wide (clipped to `x_end` and the image's `img_h`). */
static void draw_label(uint8_t *img, int img_w, int img_h, int x, int y, int x_end, int scale, const char *text) {
    for (int col = 0; text[col]; col++) {
        const uint8_t *g = font5x7_glyph(text[col]);
        if (!g) continue;
        for (int r = 0; r < 7 * scale; r++)
            for (int b = 0; b < 5 * scale; b++) {
                int px = x + col * 6 * scale + b, py = y + r;
                if (!(g[r / scale] >> (4 - b / scale) & 1) || px >= x_end || px >= img_w || py >= img_h) continue;
                uint8_t *o = img + 3 * ((size_t)py * img_w + px);
                o[0] = o[1] = o[2] = 230;
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
    uint32_t n = 0, cap_particles = st.particles > 0 ? st.particles : 1;
    float *water = malloc(sizeof(float) * 3 * cap_particles);
    if (!water) exit(1);
    wh_check(wethair_sim_get_water(sim, water, cap_particles, &n), "wethair_sim_get_water");
    for (uint32_t j = 0; j < n; j++) {
        float sx, sy, sz;
        if (!project(&cam, v3(water[3 * j], water[3 * j + 1], water[3 * j + 2]), &sx, &sy, &sz)) continue;
        for (int dy = -ss; dy <= ss; dy++)
            for (int dx = -ss; dx <= ss; dx++)
                if (dx * dx + dy * dy <= ss * ss) plot(&t, (int)sx + dx, (int)sy + dy, sz - 1e-3f, v3(0.55f, 0.75f, 1.0f));
    }
    free(water);
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

#endif
