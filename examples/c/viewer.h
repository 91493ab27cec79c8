/* The interactive viewer's shared state and the interface of its two renderers: Vulkan
 * (viewer_vk.c: wethair on the viewer's own VkDevice, strands drawn straight from the shared
 * VkBuffer) and OpenGL 3.3 (viewer_gl.c: vertices copied through host memory). viewer.c owns
 * the window's input, the simulation, the script and the figures. */
#ifndef WETHAIR_VIEWER_H
#define WETHAIR_VIEWER_H

#include <stdint.h>

#include "scene.h"

#define MAX_PARTICLES 8192
#define SPRAY_PER_FRAME 25
#define OVERLAY_LINES 4

typedef struct GLFWwindow GLFWwindow;
typedef struct Viewer Viewer;

/* What a renderer does for the viewer. */
typedef struct {
    /* Creates the simulation described by `desc` (the Vulkan renderer puts GPU simulations on
     * its own device, so their vertex buffer is the one it draws from). */
    WetHairResult (*create_sim)(Viewer *v, WetHairSimDesc *desc, WetHairSim **out);
    /* Draws the simulation's current frame and shows it; when `rgb` is not NULL, also copies
     * the frame into it (width * height * 3 bytes, top row first). */
    void (*draw)(Viewer *v, uint8_t *rgb);
    /* Says where the strands' vertices come from this frame, for the overlay. */
    const char *(*source)(const Viewer *v);
    /* Destroys the renderer and the window (after the simulation is destroyed). */
    void (*close)(Viewer *v);
} Renderer;

struct Viewer {
    /* Simulation */
    WetHairGroom *groom;
    WetHairSim *sim;
    uint32_t backend, integrator;
    int is_paper;
    float head_yaw, head_pitch, head_pos[3];
    int spraying, paused, step_once;
    /* Weather and the wet model: rain and wind toggles (both backends); --wet-model holds
     * water in the hair (the CPU backend for now) and shows the ledger. */
    int raining, windy, wet_model;
    /* Production features: every guides-th strand simulated (0: all), the simulated fraction
     * (L cycles it), hair-hair volume. */
    uint32_t guides;
    float guide_fraction;
    int volume;
    /* --sdf-head: the head is a signed distance field (a sampled sphere) that moves with the
     * head transform, instead of the analytic sphere. */
    int sdf_head;
    /* --skinned-roots: every root follows its own frame (wethair_sim_set_root_frames), here a
     * ripple that runs over the scalp while `skin_moving` (J toggles it); `rest_roots` holds
     * the roots in head space and `root_center` their mean, `root_frames` room for each
     * frame's positions and rotations (7 floats a root), `skin_time` the ripple's clock (s). */
    int skinned, skin_moving;
    float *rest_roots, *root_frames, root_center[3], skin_time;
    uint32_t root_count;
    /* --fixed-step HZ: wethair_sim_advance with each frame's time (1/60 s when scripted) in
     * fixed steps of 1/HZ s, the vertices blended between the last two; 0: a 1/60 s step a
     * frame. `advance` is the last advance's report, `last_frame_ms` when the frame before
     * began. */
    float fixed_hz;
    WetHairAdvance advance;
    double last_frame_ms;
    uint32_t seed;
    WetHairVertexLayout lay;
    /* Camera: orbit around target */
    float cam_yaw, cam_pitch, cam_dist, target[3], fov;
    double last_x, last_y;
    int dragging;
    /* Window and renderer */
    GLFWwindow *window;
    Renderer r;
    void *rs;         /* the renderer's own state */
    const char *api;  /* "Vulkan" or "OpenGL" */
    int width, height;
    int samples;      /* MSAA samples: 4 in a person's window, 1 for scripted software runs */
    float line_width; /* pixels; + and - change it */
    int validate;     /* Vulkan: enable the validation layer, count its errors */
    char overlay[OVERLAY_LINES][192];
    /* Figures */
    double sim_ms, draw_ms;
    int frames_in_window;
    /* Script */
    struct Event *events;
    int n_events, next_event;
    int scripted;
};

/* Opens the window with the Vulkan renderer; 0 with the reason in `why` when this machine's
 * Vulkan cannot (no loader, no device that presents to the window, no wethair features). */
int vk_renderer_open(Viewer *v, char *why, size_t why_len);
/* Opens the window with the OpenGL 3.3 renderer; 0 with the reason in `why` when it cannot. */
int gl_renderer_open(Viewer *v, char *why, size_t why_len);

/* Column-major view-projection in OpenGL clip space (y up, depth -1..1), z up in the world. */
void viewer_view_proj(const Viewer *v, float m[16], float eye[3]);
/* The overlay's text as flat triangles in normalised device coordinates (y up), two floats a
 * vertex; (re)allocates *buf as needed and returns the number of floats. */
size_t viewer_text_triangles(const Viewer *v, float **buf, size_t *cap);
/* Screen pixels per font pixel of the overlay (its shadow is drawn this far down and right). */
int viewer_text_scale(const Viewer *v);
/* The line-list indices of every strand segment (count returned in *n); free() them. */
uint32_t *viewer_line_indices(const WetHairVertexLayout *lay, uint32_t *n);

/* The background colour, and the light direction of the Kajiya-Kay shading (world). */
static const float VIEWER_CLEAR[3] = {0.10f, 0.10f, 0.12f};
static const float VIEWER_LIGHT[3] = {-0.4f, -0.7f, 0.6f};
/* Water particles' colour and point size in pixels. */
static const float VIEWER_WATER[3] = {0.55f, 0.75f, 1.0f};
#define VIEWER_WATER_POINT 3.0f

#endif
