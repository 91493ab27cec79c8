/* An interactive viewer: a window (GLFW, OpenGL 3.3) where a person turns the head, sprays
 * water where the cursor points, and watches the strands gather into wet bundles.
 *
 * usage: viewer [--groom FILE.tfx|.hair] [--backend auto|cpu|gpu] [--size WxH]
 *               [--script FILE] [--screenshot FILE --frames N]
 *
 * Controls: left drag orbit, wheel zoom; space or right mouse: spray at the cursor; arrows turn
 * the head (left/right yaw, up/down pitch), W/A/S/D/Q/E move it; C dry (remove all water);
 * R reset; B switch backend (CPU/GPU); I switch integrator; P pause; N single step; Esc quit.
 * Drawn in the window (and in its title, and on stdout every second): simulation and draw
 * ms/frame, backend and adapter, integrator, points, particles, the clumping measure, the
 * spray rate.
 *
 * --script FILE replays timed events, one per line: "FRAME COMMAND [ARGS]" with COMMAND one of
 *   spray on|off, yaw DEG, pitch DEG, move DX DY DZ (m), dry, reset, backend cpu|gpu|auto,
 *   integrator symplectic|implicit, pause, resume, step, screenshot FILE (.png or .ppm),
 *   stats, quit
 * In script mode the spray aims from the camera at the head, the frame step is a fixed 1/60 s
 * and every frame is stepped (no dropped frames), so runs repeat. */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <GLFW/glfw3.h>

#include "font5x7.h"
#include "png.h"
#include "scene.h"

#define MAX_PARTICLES 8192
#define SPRAY_PER_FRAME 25

typedef struct {
    int frame;
    char cmd[32];
    char arg[256];
} Event;

typedef struct {
    /* Simulation */
    WetHairGroom *groom;
    WetHairSim *sim;
    uint32_t backend, integrator;
    int is_paper;
    float head_yaw, head_pitch, head_pos[3];
    int spraying, paused, step_once;
    uint32_t seed;
    /* Camera: orbit around target */
    float cam_yaw, cam_pitch, cam_dist, target[3], fov;
    double last_x, last_y;
    int dragging;
    /* GL */
    GLuint prog, vao, vbo, ebo, water_vao, water_vbo, text_prog, text_vao, text_vbo;
    char overlay[3][192];
    float *text_verts;
    size_t text_cap;
    GLsizei index_count;
    int width, height;
    float *verts;
    size_t vert_cap;
    WetHairVertexLayout lay;
    /* Figures */
    double sim_ms, draw_ms;
    int frames_in_window;
    /* Script */
    Event *events;
    int n_events, next_event;
    int scripted;
} Viewer;

static const char *VS =
    "#version 330 core\n"
    "layout(location = 0) in vec3 in_position;\n"
    "layout(location = 1) in vec3 in_tangent;\n"
    "layout(location = 2) in float in_wetness;\n"
    "uniform mat4 view_proj;\n"
    "uniform vec3 eye;\n"
    "out vec3 v_tangent; out vec3 v_to_eye; out float v_wetness;\n"
    "void main() {\n"
    "  gl_Position = view_proj * vec4(in_position, 1.0);\n"
    "  v_tangent = in_tangent; v_to_eye = eye - in_position; v_wetness = in_wetness;\n"
    "}\n";

/* The wet-look Kajiya-Kay of bindings/shaders/kajiya_kay.frag, in GLSL 3.30. */
static const char *FS =
    "#version 330 core\n"
    "in vec3 v_tangent; in vec3 v_to_eye; in float v_wetness;\n"
    "uniform vec3 light; uniform int water;\n"
    "out vec4 color;\n"
    "void main() {\n"
    "  if (water == 1) { color = vec4(0.55, 0.75, 1.0, 1.0); return; }\n"
    "  vec3 t = normalize(v_tangent), v = normalize(v_to_eye), l = normalize(light);\n"
    "  float wet = clamp(v_wetness, 0.0, 1.0);\n"
    "  float lt = dot(l, t), vt = dot(v, t);\n"
    "  float sin_l = sqrt(max(0.0, 1.0 - lt * lt)), sin_v = sqrt(max(0.0, 1.0 - vt * vt));\n"
    "  float spec = pow(max(sin_l * sin_v - lt * vt, 0.0), 30.0 + 120.0 * wet) * (0.25 + 0.75 * wet);\n"
    "  vec3 base = vec3(0.30, 0.15, 0.06) * (1.0 - 0.6 * wet);\n"
    "  vec3 c = base * (0.2 + 0.8 * sin_l) + spec * vec3(1.0, 1.0, 0.95);\n"
    "  color = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);\n"
    "}\n";

/* The on-screen figures: flat-coloured pixels of the 5x7 font. */
static const char *TEXT_VS = "#version 330 core\nlayout(location = 0) in vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }\n";
static const char *TEXT_FS =
    "#version 330 core\nuniform vec3 tint;\nout vec4 color;\nvoid main() { color = vec4(tint, 1.0); }\n";

static GLuint compile(GLenum kind, const char *src) {
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "shader: %s\n", log);
        exit(1);
    }
    return s;
}

/* Column-major perspective * look-at (OpenGL clip space), z up. */
static void view_proj(const Viewer *v, float m[16], float eye[3]) {
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
static void make_sim(Viewer *v) {
    if (v->sim) wethair_sim_destroy(v->sim);
    WetHairSimDesc desc;
    wethair_sim_desc_default(&desc);
    WetHairCollider head = {WETHAIR_COLLIDER_SPHERE, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.1f};
    desc.groom = v->groom;
    if (v->is_paper) {
        desc.colliders = &head;
        desc.collider_count = 1;
    }
    desc.backend = v->backend;
    desc.integrator = v->integrator;
    desc.readback = WETHAIR_READBACK_LATEST;
    desc.water.capacity = MAX_PARTICLES;
    v->sim = NULL;
    WetHairResult r = wethair_sim_create(&desc, &v->sim);
    if (r != WETHAIR_OK && v->backend == WETHAIR_BACKEND_GPU) {
        fprintf(stderr, "viewer: GPU backend unavailable (%s); using the CPU\n", wethair_last_error_message());
        v->backend = WETHAIR_BACKEND_CPU;
        desc.backend = v->backend;
        r = wethair_sim_create(&desc, &v->sim);
    }
    wh_check(r, "wethair_sim_create");
    float m[16];
    head_matrix(v, m);
    wh_check(wethair_sim_set_head_transform(v->sim, m), "wethair_sim_set_head_transform");
    wh_check(wethair_sim_reset(v->sim), "wethair_sim_reset");
    wh_print_backend(v->sim);
    printf("viewer: integrator %s\n", integrator_name(v->integrator));
}

/* A cone of particles from the camera towards (dx, dy) in normalised device coordinates. */
static void spray(Viewer *v, float ndc_x, float ndc_y, uint32_t count) {
    float m[16], eye[3];
    view_proj(v, m, eye);
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

/* Draws the overlay lines at the top left, 2 screen pixels per font pixel, with a shadow. */
static void draw_text(Viewer *v) {
    const int scale = v->width >= 800 ? 2 : 1, x0 = 8, y0 = 8;
    size_t n = 0;
    for (int line = 0; line < 3; line++)
        for (const char *c = v->overlay[line]; *c; c++) n += 35;
    if (n * 12 > v->text_cap) {
        free(v->text_verts);
        v->text_cap = n * 12;
        v->text_verts = malloc(v->text_cap * sizeof(float));
        if (!v->text_verts) exit(1);
    }
    size_t k = 0;
    float sx = 2.0f / (float)v->width, sy = 2.0f / (float)v->height;
    for (int line = 0; line < 3; line++) {
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
                    memcpy(v->text_verts + k, q, sizeof q);
                    k += 12;
                }
        }
    }
    if (!k) return;
    glDisable(GL_DEPTH_TEST);
    glUseProgram(v->text_prog);
    glBindVertexArray(v->text_vao);
    glBindBuffer(GL_ARRAY_BUFFER, v->text_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(k * sizeof(float)), v->text_verts, GL_STREAM_DRAW);
    GLint tint = glGetUniformLocation(v->text_prog, "tint");
    /* The shadow, one font pixel down and right, then the text. */
    float dx = (float)scale * sx, dy = (float)scale * sy;
    for (size_t i = 0; i < k; i += 2) {
        v->text_verts[i] += dx;
        v->text_verts[i + 1] -= dy;
    }
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(k * sizeof(float)), v->text_verts);
    glUniform3f(tint, 0.0f, 0.0f, 0.0f);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(k / 2));
    for (size_t i = 0; i < k; i += 2) {
        v->text_verts[i] -= dx;
        v->text_verts[i + 1] += dy;
    }
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(k * sizeof(float)), v->text_verts);
    glUniform3f(tint, 0.95f, 0.95f, 0.85f);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(k / 2));
    glEnable(GL_DEPTH_TEST);
}

static void save_screenshot(const Viewer *v, const char *path) {
    size_t n = (size_t)v->width * v->height * 3;
    uint8_t *px = malloc(n), *flip = malloc(n);
    if (!px || !flip) exit(1);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, v->width, v->height, GL_RGB, GL_UNSIGNED_BYTE, px);
    for (int y = 0; y < v->height; y++)
        memcpy(flip + (size_t)y * v->width * 3, px + (size_t)(v->height - 1 - y) * v->width * 3, (size_t)v->width * 3);
    size_t len = strlen(path);
    int fail;
    if (len > 4 && !strcmp(path + len - 4, ".ppm")) {
        FILE *f = fopen(path, "wb");
        fail = !f;
        if (f) {
            fprintf(f, "P6\n%d %d\n255\n", v->width, v->height);
            fail = fwrite(flip, 1, n, f) != n;
            fclose(f);
        }
    } else {
        fail = png_write(path, flip, v->width, v->height);
    }
    free(px);
    free(flip);
    if (fail) {
        fprintf(stderr, "could not write %s\n", path);
        exit(1);
    }
    WetHairStats st = wh_stats(v->sim);
    printf("viewer: screenshot %s: clumping %.5f m, %u particles\n", path, st.clumping, st.particles);
}

static void print_stats(Viewer *v, GLFWwindow *win) {
    WetHairStats st = wh_stats(v->sim);
    WetHairBackendInfo info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    wh_check(wethair_sim_get_backend_info(v->sim, &info), "wethair_sim_get_backend_info");
    int n = v->frames_in_window ? v->frames_in_window : 1;
    char title[512];
    snprintf(title, sizeof title,
             "wethair | sim %.2f ms  draw %.2f ms | %s %s | %s | %u points, %u particles | clumping %.4f m%s",
             v->sim_ms / n, v->draw_ms / n, info.backend == WETHAIR_BACKEND_GPU ? "GPU" : "CPU", info.device,
             integrator_name(v->integrator), st.points, st.particles, st.clumping, v->paused ? " | paused" : "");
    glfwSetWindowTitle(win, title);
    printf("%s\n", title);
    snprintf(v->overlay[0], sizeof v->overlay[0], "SIM %.2f MS  DRAW %.2f MS  %s %s", v->sim_ms / n, v->draw_ms / n,
             info.backend == WETHAIR_BACKEND_GPU ? "GPU" : "CPU", info.device);
    snprintf(v->overlay[1], sizeof v->overlay[1], "%s  %u POINTS  %u PARTICLES  CLUMPING %.2f MM",
             integrator_name(v->integrator), st.points, st.particles, 1e3 * st.clumping);
    snprintf(v->overlay[2], sizeof v->overlay[2], "SPRAY %d PARTICLES/S (SPACE, RIGHT MOUSE)%s", SPRAY_PER_FRAME * 60,
             v->paused ? "  PAUSED" : "");
    v->sim_ms = v->draw_ms = 0.0;
    v->frames_in_window = 0;
}

static void run_event(Viewer *v, GLFWwindow *win, const Event *e) {
    if (!strcmp(e->cmd, "spray")) v->spraying = !strcmp(e->arg, "on");
    else if (!strcmp(e->cmd, "yaw")) v->head_yaw = (float)atof(e->arg) * 3.14159265f / 180.0f;
    else if (!strcmp(e->cmd, "pitch")) v->head_pitch = (float)atof(e->arg) * 3.14159265f / 180.0f;
    else if (!strcmp(e->cmd, "move")) sscanf(e->arg, "%f %f %f", &v->head_pos[0], &v->head_pos[1], &v->head_pos[2]);
    else if (!strcmp(e->cmd, "dry")) wh_check(wethair_sim_clear_water(v->sim), "wethair_sim_clear_water");
    else if (!strcmp(e->cmd, "reset")) wh_check(wethair_sim_reset(v->sim), "wethair_sim_reset");
    else if (!strcmp(e->cmd, "backend")) {
        v->backend = wh_parse_backend(e->arg);
        make_sim(v);
    } else if (!strcmp(e->cmd, "integrator")) {
        v->integrator = !strcmp(e->arg, "implicit") ? WETHAIR_INTEGRATOR_IMPLICIT_EULER : WETHAIR_INTEGRATOR_SYMPLECTIC_EULER;
        make_sim(v);
    } else if (!strcmp(e->cmd, "pause")) v->paused = 1;
    else if (!strcmp(e->cmd, "resume")) v->paused = 0;
    else if (!strcmp(e->cmd, "step")) v->step_once = 1;
    else if (!strcmp(e->cmd, "screenshot")) save_screenshot(v, e->arg);
    else if (!strcmp(e->cmd, "stats")) print_stats(v, win);
    else if (!strcmp(e->cmd, "quit")) glfwSetWindowShouldClose(win, 1);
    else {
        fprintf(stderr, "script: unknown command %s\n", e->cmd);
        exit(2);
    }
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
    if (action != GLFW_PRESS) return;
    switch (key) {
    case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(win, 1); break;
    case GLFW_KEY_C: wh_check(wethair_sim_clear_water(v->sim), "wethair_sim_clear_water"); break;
    case GLFW_KEY_R: wh_check(wethair_sim_reset(v->sim), "wethair_sim_reset"); break;
    case GLFW_KEY_P: v->paused = !v->paused; break;
    case GLFW_KEY_N: v->step_once = 1; break;
    case GLFW_KEY_B:
        v->backend = v->backend == WETHAIR_BACKEND_CPU ? WETHAIR_BACKEND_GPU : WETHAIR_BACKEND_CPU;
        make_sim(v);
        break;
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
    size_t written = 0;
    wh_check(wethair_sim_get_vertex_buffer(v->sim, v->verts, v->vert_cap, &written), "wethair_sim_get_vertex_buffer");
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    int po = v->lay.position_offset / 4;
    for (uint32_t i = 0; i < v->lay.vertex_count; i++)
        for (int k = 0; k < 3; k++) {
            float x = v->verts[(size_t)i * v->lay.stride_floats + po + k];
            lo[k] = fminf(lo[k], x);
            hi[k] = fmaxf(hi[k], x);
        }
    float radius = 0.0f;
    for (int k = 0; k < 3; k++) {
        v->target[k] = 0.5f * (lo[k] + hi[k]);
        radius = fmaxf(radius, 0.5f * (hi[k] - lo[k]));
    }
    v->target[2] -= 0.3f * radius; /* room for the hair to fall */
    v->cam_dist = 1.4f * radius / tanf(0.5f * v->fov);
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
    const char *groom_path = NULL, *shot = NULL, *script = NULL;
    int frames = 0;
    for (int i = 1; i < argc; i++) {
        if (i + 1 < argc && !strcmp(argv[i], "--groom")) groom_path = argv[++i];
        else if (i + 1 < argc && !strcmp(argv[i], "--backend")) v.backend = wh_parse_backend(argv[++i]);
        else if (i + 1 < argc && !strcmp(argv[i], "--script")) script = argv[++i];
        else if (i + 1 < argc && !strcmp(argv[i], "--screenshot")) shot = argv[++i];
        else if (i + 1 < argc && !strcmp(argv[i], "--frames")) frames = atoi(argv[++i]);
        else if (i + 1 < argc && !strcmp(argv[i], "--size")) sscanf(argv[++i], "%dx%d", &v.width, &v.height);
        else {
            fprintf(stderr,
                    "usage: %s [--groom FILE] [--backend auto|cpu|gpu] [--size WxH] [--script FILE] "
                    "[--screenshot FILE --frames N]\n",
                    argv[0]);
            return 2;
        }
    }
    if (script) load_script(&v, script);
    if (shot && frames <= 0) frames = 120;
    if (!glfwInit()) {
        fprintf(stderr, "viewer: GLFW could not start (no display? try xvfb-run)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    /* Antialiased lines where it is cheap: a person's window, not the scripted software runs. */
    glfwWindowHint(GLFW_SAMPLES, script || shot ? 0 : 4);
    GLFWwindow *win = glfwCreateWindow(v.width, v.height, "wethair", NULL, NULL);
    if (!win) {
        fprintf(stderr, "viewer: no OpenGL 3.3 window\n");
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(win);
    glfwSwapInterval(v.scripted || shot ? 0 : 1);
    glfwSetWindowUserPointer(win, &v);
    glfwSetKeyCallback(win, on_key);
    glfwSetScrollCallback(win, on_scroll);
    glfwGetFramebufferSize(win, &v.width, &v.height);
    printf("viewer: OpenGL %s on %s, drawing from the copy path (the Vulkan shared-buffer path is not built yet)\n",
           (const char *)glGetString(GL_VERSION), (const char *)glGetString(GL_RENDERER));

    if (groom_path) wh_check(wethair_groom_load(groom_path, 1e-3f, &v.groom), "wethair_groom_load");
    else wh_check(wethair_groom_create_paper_scene(10000, 6, &v.groom), "wethair_groom_create_paper_scene");
    v.is_paper = groom_path == NULL;
    make_sim(&v);
    v.lay.struct_size = sizeof v.lay;
    wh_check(wethair_sim_get_vertex_layout(v.sim, &v.lay), "wethair_sim_get_vertex_layout");
    v.vert_cap = (size_t)v.lay.vertex_count * v.lay.stride_floats;
    v.verts = malloc(v.vert_cap * sizeof(float));
    if (!v.verts) return 1;
    fit_camera(&v);

    /* GL objects: the hair (vertex buffer + line-list indices) and the water (points). */
    v.prog = glCreateProgram();
    GLuint vs = compile(GL_VERTEX_SHADER, VS), fs = compile(GL_FRAGMENT_SHADER, FS);
    glAttachShader(v.prog, vs);
    glAttachShader(v.prog, fs);
    glLinkProgram(v.prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint linked = 0;
    glGetProgramiv(v.prog, GL_LINK_STATUS, &linked);
    if (!linked) return fprintf(stderr, "viewer: shader link failed\n"), 1;
    glGenVertexArrays(1, &v.vao);
    glBindVertexArray(v.vao);
    glGenBuffers(1, &v.vbo);
    glBindBuffer(GL_ARRAY_BUFFER, v.vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(v.vert_cap * sizeof(float)), NULL, GL_STREAM_DRAW);
    GLsizei stride = (GLsizei)(v.lay.stride_floats * 4);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, (void *)(intptr_t)v.lay.position_offset);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, (void *)(intptr_t)v.lay.tangent_offset);
    glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride, (void *)(intptr_t)v.lay.wetness_offset);
    for (GLuint a = 0; a < 3; a++) glEnableVertexAttribArray(a);
    uint32_t per = v.lay.vertex_count / v.lay.strand_count;
    v.index_count = (GLsizei)(v.lay.strand_count * (per - 1) * 2);
    uint32_t *ix = malloc(sizeof(uint32_t) * (size_t)v.index_count);
    if (!ix) return 1;
    for (uint32_t s = 0, k = 0; s < v.lay.strand_count; s++)
        for (uint32_t i = 0; i + 1 < per; i++) {
            ix[k++] = s * per + i;
            ix[k++] = s * per + i + 1;
        }
    glGenBuffers(1, &v.ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, v.ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * (size_t)v.index_count), ix, GL_STATIC_DRAW);
    free(ix);
    glGenVertexArrays(1, &v.water_vao);
    glBindVertexArray(v.water_vao);
    glGenBuffers(1, &v.water_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, v.water_vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof(float) * 3 * MAX_PARTICLES, NULL, GL_STREAM_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, 0);
    glEnableVertexAttribArray(0);
    glVertexAttrib3f(1, 0.0f, 0.0f, 1.0f);
    glVertexAttrib1f(2, 0.0f);
    v.text_prog = glCreateProgram();
    vs = compile(GL_VERTEX_SHADER, TEXT_VS);
    fs = compile(GL_FRAGMENT_SHADER, TEXT_FS);
    glAttachShader(v.text_prog, vs);
    glAttachShader(v.text_prog, fs);
    glLinkProgram(v.text_prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    glGenVertexArrays(1, &v.text_vao);
    glBindVertexArray(v.text_vao);
    glGenBuffers(1, &v.text_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, v.text_vbo);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 8, 0);
    glEnableVertexAttribArray(0);
    snprintf(v.overlay[0], sizeof v.overlay[0], "WETHAIR %s", wethair_version_string());
    float *water = malloc(sizeof(float) * 3 * MAX_PARTICLES);
    if (!water) return 1;
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);

    int frame = 0;
    double last_print = wh_now_ms();
    while (!glfwWindowShouldClose(win)) {
        glfwPollEvents();
        while (v.next_event < v.n_events && v.events[v.next_event].frame <= frame) run_event(&v, win, &v.events[v.next_event++]);
        if (glfwWindowShouldClose(win)) break;
        /* Interactive input: orbit, spray, head. */
        double mx, my;
        glfwGetCursorPos(win, &mx, &my);
        int left = glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
        if (left && v.dragging) {
            v.cam_yaw -= 0.005f * (float)(mx - v.last_x);
            v.cam_pitch = fminf(1.4f, fmaxf(-1.4f, v.cam_pitch + 0.005f * (float)(my - v.last_y)));
        }
        v.dragging = left;
        v.last_x = mx;
        v.last_y = my;
        float step_rad = 0.03f, step_m = 0.005f;
        if (glfwGetKey(win, GLFW_KEY_LEFT) == GLFW_PRESS) v.head_yaw += step_rad;
        if (glfwGetKey(win, GLFW_KEY_RIGHT) == GLFW_PRESS) v.head_yaw -= step_rad;
        if (glfwGetKey(win, GLFW_KEY_UP) == GLFW_PRESS) v.head_pitch += step_rad;
        if (glfwGetKey(win, GLFW_KEY_DOWN) == GLFW_PRESS) v.head_pitch -= step_rad;
        if (glfwGetKey(win, GLFW_KEY_W) == GLFW_PRESS) v.head_pos[1] += step_m;
        if (glfwGetKey(win, GLFW_KEY_S) == GLFW_PRESS) v.head_pos[1] -= step_m;
        if (glfwGetKey(win, GLFW_KEY_A) == GLFW_PRESS) v.head_pos[0] -= step_m;
        if (glfwGetKey(win, GLFW_KEY_D) == GLFW_PRESS) v.head_pos[0] += step_m;
        if (glfwGetKey(win, GLFW_KEY_Q) == GLFW_PRESS) v.head_pos[2] += step_m;
        if (glfwGetKey(win, GLFW_KEY_E) == GLFW_PRESS) v.head_pos[2] -= step_m;
        int spray_now = v.spraying || glfwGetKey(win, GLFW_KEY_SPACE) == GLFW_PRESS ||
                        glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
        if (spray_now) {
            float nx = v.scripted ? 0.0f : (float)(2.0 * mx / v.width - 1.0), ny = v.scripted ? 0.0f : (float)(1.0 - 2.0 * my / v.height);
            spray(&v, nx, ny, SPRAY_PER_FRAME);
        }
        float hm[16];
        head_matrix(&v, hm);
        wh_check(wethair_sim_set_head_transform(v.sim, hm), "wethair_sim_set_head_transform");

        double t0 = wh_now_ms();
        if (!v.paused || v.step_once) {
            wh_check(wethair_sim_step(v.sim, 1.0f / 60.0f), "wethair_sim_step");
            v.step_once = 0;
        }
        size_t written = 0;
        wh_check(wethair_sim_get_vertex_buffer(v.sim, v.verts, v.vert_cap, &written), "wethair_sim_get_vertex_buffer");
        uint32_t nw = 0;
        wh_check(wethair_sim_get_water(v.sim, water, MAX_PARTICLES, &nw), "wethair_sim_get_water");
        double t1 = wh_now_ms();

        glViewport(0, 0, v.width, v.height);
        glClearColor(0.10f, 0.10f, 0.12f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        float m[16], eye[3];
        view_proj(&v, m, eye);
        glUseProgram(v.prog);
        glUniformMatrix4fv(glGetUniformLocation(v.prog, "view_proj"), 1, GL_FALSE, m);
        glUniform3f(glGetUniformLocation(v.prog, "eye"), eye[0], eye[1], eye[2]);
        glUniform3f(glGetUniformLocation(v.prog, "light"), -0.4f, -0.7f, 0.6f);
        glUniform1i(glGetUniformLocation(v.prog, "water"), 0);
        glBindVertexArray(v.vao);
        glBindBuffer(GL_ARRAY_BUFFER, v.vbo);
        glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(written * sizeof(float)), v.verts);
        glDrawElements(GL_LINES, v.index_count, GL_UNSIGNED_INT, 0);
        if (nw) {
            glUniform1i(glGetUniformLocation(v.prog, "water"), 1);
            glBindVertexArray(v.water_vao);
            glBindBuffer(GL_ARRAY_BUFFER, v.water_vbo);
            glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(sizeof(float) * 3 * nw), water);
            glPointSize(3.0f);
            glDrawArrays(GL_POINTS, 0, (GLsizei)nw);
        }
        draw_text(&v);
        glFinish();
        double t2 = wh_now_ms();
        v.sim_ms += t1 - t0;
        v.draw_ms += t2 - t1;
        v.frames_in_window++;
        frame++;
        if (shot && frame == frames) {
            save_screenshot(&v, shot);
            glfwSetWindowShouldClose(win, 1);
        }
        glfwSwapBuffers(win);
        if (wh_now_ms() - last_print > 1000.0) {
            print_stats(&v, win);
            last_print = wh_now_ms();
        }
    }
    print_stats(&v, win);
    free(water);
    free(v.verts);
    free(v.text_verts);
    glDeleteBuffers(1, &v.text_vbo);
    glDeleteVertexArrays(1, &v.text_vao);
    glDeleteProgram(v.text_prog);
    free(v.events);
    glDeleteBuffers(1, &v.vbo);
    glDeleteBuffers(1, &v.ebo);
    glDeleteBuffers(1, &v.water_vbo);
    glDeleteVertexArrays(1, &v.vao);
    glDeleteVertexArrays(1, &v.water_vao);
    glDeleteProgram(v.prog);
    wethair_sim_destroy(v.sim);
    wethair_groom_destroy(v.groom);
    glfwDestroyWindow(win);
    glfwTerminate();
    return 0;
}
