/* The viewer's OpenGL 3.3 renderer: the copy path. Each frame the strands' vertices and the
 * water's positions are copied out of wethair into host memory and uploaded; the strands are
 * drawn as depth-tested lines with the wet-look Kajiya-Kay of bindings/shaders (in GLSL 3.30),
 * the water as points, the figures as flat quads. Used where Vulkan cannot draw. */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <GLFW/glfw3.h>

#include "viewer.h"

typedef struct {
    GLuint prog, vao, vbo, ebo, water_vao, water_vbo, flat_prog, text_vao, text_vbo;
    GLsizei index_count;
    float *verts, *water, *text;
    size_t vert_cap, text_cap;
    float max_line_width;
} Gl;

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
    "uniform vec3 light;\n"
    "out vec4 color;\n"
    "void main() {\n"
    "  vec3 t = normalize(v_tangent), v = normalize(v_to_eye), l = normalize(light);\n"
    "  float wet = clamp(v_wetness, 0.0, 1.0);\n"
    "  float lt = dot(l, t), vt = dot(v, t);\n"
    "  float sin_l = sqrt(max(0.0, 1.0 - lt * lt)), sin_v = sqrt(max(0.0, 1.0 - vt * vt));\n"
    "  float spec = pow(max(sin_l * sin_v - lt * vt, 0.0), 30.0 + 120.0 * wet) * (0.25 + 0.75 * wet);\n"
    "  vec3 base = vec3(0.30, 0.15, 0.06) * (1.0 - 0.6 * wet);\n"
    "  vec3 c = base * (0.2 + 0.8 * sin_l) + spec * vec3(1.0, 1.0, 0.95);\n"
    "  color = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);\n"
    "}\n";

/* Water and the figures: flat colour, positions through a matrix (the text's is a shift). */
static const char *FLAT_VS =
    "#version 330 core\n"
    "layout(location = 0) in vec3 p;\n"
    "uniform mat4 view_proj;\n"
    "void main() { gl_Position = view_proj * vec4(p, 1.0); }\n";
static const char *FLAT_FS =
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

static GLuint program(const char *vs_src, const char *fs_src) {
    GLuint p = glCreateProgram(), vs = compile(GL_VERTEX_SHADER, vs_src), fs = compile(GL_FRAGMENT_SHADER, fs_src);
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint linked = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &linked);
    if (!linked) {
        fprintf(stderr, "viewer: shader link failed\n");
        exit(1);
    }
    return p;
}

static WetHairResult gl_create_sim(Viewer *v, WetHairSimDesc *desc, WetHairSim **out) {
    (void)v;
    return wethair_sim_create(desc, out);
}

static const char *gl_source(const Viewer *v) {
    (void)v;
    return "copy path";
}

/* The buffers sized by the groom: made at the first frame (the layout comes with the sim). */
static void gl_buffers(Viewer *v, Gl *g) {
    g->vert_cap = (size_t)v->lay.vertex_count * v->lay.stride_floats;
    g->verts = malloc(g->vert_cap * sizeof(float));
    g->water = malloc(sizeof(float) * 3 * MAX_PARTICLES);
    if (!g->verts || !g->water) exit(1);
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(1, &g->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(g->vert_cap * sizeof(float)), NULL, GL_STREAM_DRAW);
    GLsizei stride = (GLsizei)(v->lay.stride_floats * 4);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, (void *)(intptr_t)v->lay.position_offset);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, (void *)(intptr_t)v->lay.tangent_offset);
    glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride, (void *)(intptr_t)v->lay.wetness_offset);
    for (GLuint a = 0; a < 3; a++) glEnableVertexAttribArray(a);
    uint32_t n = 0, *ix = viewer_line_indices(&v->lay, &n);
    g->index_count = (GLsizei)n;
    glGenBuffers(1, &g->ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * n), ix, GL_STATIC_DRAW);
    free(ix);
}

static void set_matrix(GLuint prog, const float m[16]) {
    glUniformMatrix4fv(glGetUniformLocation(prog, "view_proj"), 1, GL_FALSE, m);
}

/* The overlay: its shadow one font pixel down and right, then the text. */
static void gl_text(Viewer *v, Gl *g) {
    size_t k = viewer_text_triangles(v, &g->text, &g->text_cap);
    if (!k) return;
    glDisable(GL_DEPTH_TEST);
    glUseProgram(g->flat_prog);
    glBindVertexArray(g->text_vao);
    glBindBuffer(GL_ARRAY_BUFFER, g->text_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(k * sizeof(float)), g->text, GL_STREAM_DRAW);
    float shift[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    shift[12] = 2.0f * (float)viewer_text_scale(v) / (float)v->width;
    shift[13] = -2.0f * (float)viewer_text_scale(v) / (float)v->height;
    GLint tint = glGetUniformLocation(g->flat_prog, "tint");
    set_matrix(g->flat_prog, shift);
    glUniform3f(tint, 0.0f, 0.0f, 0.0f);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(k / 2));
    shift[12] = shift[13] = 0.0f;
    set_matrix(g->flat_prog, shift);
    glUniform3f(tint, 0.95f, 0.95f, 0.85f);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(k / 2));
    glEnable(GL_DEPTH_TEST);
}

static void gl_draw(Viewer *v, uint8_t *rgb) {
    Gl *g = v->rs;
    if (!g->verts) gl_buffers(v, g);
    size_t written = 0;
    wh_check(wethair_sim_get_vertex_buffer(v->sim, g->verts, g->vert_cap, &written), "wethair_sim_get_vertex_buffer");
    uint32_t nw = 0;
    wh_check(wethair_sim_get_water(v->sim, g->water, MAX_PARTICLES, &nw), "wethair_sim_get_water");
    glfwGetFramebufferSize(v->window, &v->width, &v->height);
    glViewport(0, 0, v->width, v->height);
    glClearColor(VIEWER_CLEAR[0], VIEWER_CLEAR[1], VIEWER_CLEAR[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    float m[16], eye[3];
    viewer_view_proj(v, m, eye);
    glUseProgram(g->prog);
    set_matrix(g->prog, m);
    glUniform3f(glGetUniformLocation(g->prog, "eye"), eye[0], eye[1], eye[2]);
    glUniform3f(glGetUniformLocation(g->prog, "light"), VIEWER_LIGHT[0], VIEWER_LIGHT[1], VIEWER_LIGHT[2]);
    glLineWidth(fminf(v->line_width, g->max_line_width));
    glBindVertexArray(g->vao);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(written * sizeof(float)), g->verts);
    glDrawElements(GL_LINES, g->index_count, GL_UNSIGNED_INT, 0);
    if (nw) {
        glUseProgram(g->flat_prog);
        set_matrix(g->flat_prog, m);
        glUniform3f(glGetUniformLocation(g->flat_prog, "tint"), VIEWER_WATER[0], VIEWER_WATER[1], VIEWER_WATER[2]);
        glBindVertexArray(g->water_vao);
        glBindBuffer(GL_ARRAY_BUFFER, g->water_vbo);
        glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(sizeof(float) * 3 * nw), g->water);
        glPointSize(VIEWER_WATER_POINT);
        glDrawArrays(GL_POINTS, 0, (GLsizei)nw);
    }
    gl_text(v, g);
    if (rgb) {
        /* GL's rows start at the bottom. */
        size_t row = (size_t)v->width * 3;
        uint8_t *px = malloc(row * v->height);
        if (!px) exit(1);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, v->width, v->height, GL_RGB, GL_UNSIGNED_BYTE, px);
        for (int y = 0; y < v->height; y++) memcpy(rgb + (size_t)y * row, px + (size_t)(v->height - 1 - y) * row, row);
        free(px);
    }
    glFinish(); /* so the draw figure is the frame's whole cost */
    glfwSwapBuffers(v->window);
}

static void gl_close(Viewer *v) {
    Gl *g = v->rs;
    glDeleteBuffers(1, &g->vbo);
    glDeleteBuffers(1, &g->ebo);
    glDeleteBuffers(1, &g->water_vbo);
    glDeleteBuffers(1, &g->text_vbo);
    glDeleteVertexArrays(1, &g->vao);
    glDeleteVertexArrays(1, &g->water_vao);
    glDeleteVertexArrays(1, &g->text_vao);
    glDeleteProgram(g->prog);
    glDeleteProgram(g->flat_prog);
    free(g->verts);
    free(g->water);
    free(g->text);
    free(g);
    glfwDestroyWindow(v->window);
    v->window = NULL;
}

int gl_renderer_open(Viewer *v, char *why, size_t why_len) {
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_SAMPLES, v->samples > 1 ? v->samples : 0);
    v->window = glfwCreateWindow(v->width, v->height, "wethair", NULL, NULL);
    if (!v->window) {
        snprintf(why, why_len, "no OpenGL 3.3 core context");
        return 0;
    }
    Gl *g = calloc(1, sizeof *g);
    if (!g) exit(1);
    v->rs = g;
    v->api = "OpenGL";
    v->r.create_sim = gl_create_sim;
    v->r.draw = gl_draw;
    v->r.source = gl_source;
    v->r.close = gl_close;
    glfwMakeContextCurrent(v->window);
    glfwSwapInterval(v->scripted || v->samples == 1 ? 0 : 1);
    glfwGetFramebufferSize(v->window, &v->width, &v->height);
    printf("viewer: drawing with OpenGL %s on %s from the copy path\n", (const char *)glGetString(GL_VERSION),
           (const char *)glGetString(GL_RENDERER));
    g->prog = program(VS, FS);
    g->flat_prog = program(FLAT_VS, FLAT_FS);
    glGenVertexArrays(1, &g->water_vao);
    glBindVertexArray(g->water_vao);
    glGenBuffers(1, &g->water_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->water_vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof(float) * 3 * MAX_PARTICLES, NULL, GL_STREAM_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, 0);
    glEnableVertexAttribArray(0);
    glGenVertexArrays(1, &g->text_vao);
    glBindVertexArray(g->text_vao);
    glGenBuffers(1, &g->text_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->text_vbo);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 8, 0);
    glEnableVertexAttribArray(0);
    float range[2] = {1.0f, 1.0f};
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
    g->max_line_width = range[1];
    glEnable(GL_DEPTH_TEST);
    return 1;
}
