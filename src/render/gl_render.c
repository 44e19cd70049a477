/* gl_render.c: the renderer's GL layer (see gl_render.h). */
#include "render/gl_render.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clocks.h"
#include "render/gl_api.h"
#include "render/gl_context.h"
#include "render/gl_util.h"

/* The scene shader's variants, each with its kind of shading folded in as
 * constants: llvmpipe runs both sides of a branch for every pixel, so one
 * shader for all paid the rod's highlight and the plane's fade on every
 * pixel of every surface. */
/* The _CACHED variants draw the static picture once into the receivers'
 * cache (receiver_cache): the flat lines and the matte receivers. */
enum {
    SHADE_FLAT, SHADE_GLOSSY, SHADE_MATTE, SHADE_MATTE_FADED,
    SHADE_FLAT_CACHED, SHADE_MATTE_CACHED, SHADE_MATTE_FADED_CACHED, SHADE_VARIANTS
};
static const char *const shade_defines[SHADE_VARIANTS] = {
    [SHADE_FLAT] = "#define LIT 0\n#define FADING 0\n#define CACHE 0\n",
    [SHADE_GLOSSY] = "#define LIT 1\n#define FADING 0\n#define CACHE 0\n",
    [SHADE_MATTE] = "#define LIT 2\n#define FADING 0\n#define CACHE 0\n",
    [SHADE_MATTE_FADED] = "#define LIT 2\n#define FADING 1\n#define CACHE 0\n",
    [SHADE_FLAT_CACHED] = "#define LIT 0\n#define FADING 0\n#define CACHE 1\n",
    [SHADE_MATTE_CACHED] = "#define LIT 2\n#define FADING 0\n#define CACHE 1\n",
    [SHADE_MATTE_FADED_CACHED] = "#define LIT 2\n#define FADING 1\n#define CACHE 1\n",
};

typedef struct scene_program {
    GLuint id;
    GLint u_view_projection, u_orthographic, u_eye, u_view_direction, u_key, u_fill;
    GLint u_shadows, u_shadow_map, u_light, u_shadow_offset;
    GLint u_fade, u_fade_end, u_background;
    GLint u_unshadowed;
} scene_program;

struct gl_renderer {
    gl_context *context;
    gl_target *target;
    int width, height;          /* the target's, pixels */
    scene_program programs[SHADE_VARIANTS];
    GLuint vao, vbo, ibo;       /* per-frame triangles */
    GLuint line_vao, line_vbo;  /* static lines */
    int max_vertices, max_indices, max_line_vertices, line_count;
    unsigned char *box_pixels; /* (height x width x 4), RGBA of the last read rectangle */
    /* static receivers (surfaces, ground, wound): drawn in the backdrop and in every box */
    GLuint receiver_vao, receiver_vbo, receiver_ibo;
    int receiver_plane_indices, receiver_indices; /* planes first (faded), then the rest */
    int whole_boxes;            /* 1: boxes drawn whole even without receivers */
    float fade[4], fade_end, background_rgb[3];
    /* the shadow map: a depth texture the casters are drawn into from the key light */
    int shadow_size;
    GLuint shadow_program, shadow_fbo, shadow_texture;
    GLint u_shadow_light;
    float light[16], shadow_offset;
    float unshadowed[4];        /* xyz: faces of this normal receive no shadow; w 1: on */
    int shadow_drawn[4];        /* texels x0, y0, x1, y1 the last depth pass may have drawn
                                   (x0 >= x1: none); the rest of the map is cleared */
    /* the receivers' cache, for a still camera and a target without samples:
     * the lines and receivers drawn once (depth, and for each pixel of a
     * receiver lit by the key light its shadow map's look-up and the colour
     * the key light adds); a frame's boxes take their depth from it and are
     * otherwise transparent, the backdrop under them darkened on the CPU
     * where the shadow map says the key light is blocked
     * (gl_renderer_darken) */
    GLuint cache_fbo, cache_color, cache_depth, cache_look_up, cache_key;
    int cache_valid, cached;    /* cached: the last boxes were drawn from it */
    int cache_failed;           /* 1: it could not be made; boxes are drawn whole */
    float cache_camera[16], cache_light[16], cache_offset; /* what it was drawn with */
    struct map_look_up *look_ups; /* (height x width, rows bottom-up) */
    unsigned short *key_colors; /* (height x width x 3): the key light's colour, 1/256 of a level */
    float *map;                 /* (shadow_size^2): the shadow map's depths, read back */
    int map_read[4];            /* texels x0, y0, x1, y1 read into map (the rest 1: cleared) */
    float *block_least;         /* per block of MAP_BLOCK^2 texels, the least depth of its
                                   texels and of the next column and row's (1: none drawn) */
    unsigned short *block_lit;  /* the same in look-ups' depths: ref <= it is lit */
    struct tile_reach *tiles;   /* (tiles_x x tiles_y, rows bottom-up) */
    int tiles_x, tiles_y;
    int blocks;                 /* blocks a side */
};

/* A receiver pixel's look-up in the shadow map (its coordinates fixed by
 * the still camera and light): the 2 x 2 texels from (i0, j0) (the second
 * column and row clamped to the map's edge; j0 LOOK_UP_NONE: no look-up,
 * the pixel is no receiver lit by the key), the bilinear weights of the
 * second column and row (1/255), the depth compared (1/65535). 8 bytes: a
 * frame streams them over every pixel of its boxes. */
typedef struct map_look_up {
    unsigned short i0, j0;
    unsigned char wx, wy;
    unsigned short ref;
} map_look_up;
#define LOOK_UP_NONE 0xffff
/* What the look-ups of a tile of DARKEN_TILE^2 pixels reach: the blocks
 * (bx0..bx1, by0..by1; bx0 > bx1: no look-up) and the largest depth
 * compared. A tile whose blocks hold nothing nearer the light than that is
 * lit whole: its pixels are not read (they were most of the time). */
typedef struct tile_reach {
    unsigned short bx0, bx1, by0, by1, ref;
} tile_reach;
#define DARKEN_TILE 32
/* texels a side of the blocks whose least depth rejects most look-ups at once */
#define MAP_BLOCK 8

static void set_vertex_layout(void)
{
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(render_vertex),
                          (const void *)offsetof(render_vertex, position));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(render_vertex),
                          (const void *)offsetof(render_vertex, normal));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, sizeof(render_vertex),
                          (const void *)offsetof(render_vertex, color));
}

gl_renderer *gl_renderer_create(int width, int height, int samples, int max_vertices,
                                int max_indices, int max_line_vertices, char *err, size_t errlen)
{
    gl_renderer *r = calloc(1, sizeof *r);
    if (!r) {
        snprintf(err, errlen, "gl: out of memory");
        return NULL;
    }
    /* The default framebuffer is unused (we draw offscreen): keep it tiny. */
    r->context = gl_context_create(16, 16, err, errlen);
    if (!r->context) {
        free(r);
        return NULL;
    }
    r->box_pixels = malloc((size_t)width * (size_t)height * 4);
    if (!r->box_pixels) {
        snprintf(err, errlen, "gl: out of memory");
        gl_renderer_destroy(r);
        return NULL;
    }
    r->width = width;
    r->height = height;
    r->target = gl_target_create(width, height, samples, err, errlen);
    if (!r->target) {
        gl_renderer_destroy(r);
        return NULL;
    }
    for (int v = 0; v < SHADE_VARIANTS; v++) {
        scene_program *p = &r->programs[v];
        p->id = gl_program_load_defined("scene", shade_defines[v], err, errlen);
        if (!p->id) {
            gl_renderer_destroy(r);
            return NULL;
        }
        p->u_view_projection = glGetUniformLocation(p->id, "view_projection");
        p->u_orthographic = glGetUniformLocation(p->id, "orthographic");
        p->u_eye = glGetUniformLocation(p->id, "eye");
        p->u_view_direction = glGetUniformLocation(p->id, "view_direction");
        p->u_key = glGetUniformLocation(p->id, "key_direction");
        p->u_fill = glGetUniformLocation(p->id, "fill_direction");
        p->u_shadows = glGetUniformLocation(p->id, "shadows");
        p->u_shadow_map = glGetUniformLocation(p->id, "shadow_map");
        p->u_light = glGetUniformLocation(p->id, "light_view_projection");
        p->u_shadow_offset = glGetUniformLocation(p->id, "shadow_offset");
        p->u_fade = glGetUniformLocation(p->id, "fade");
        p->u_fade_end = glGetUniformLocation(p->id, "fade_end");
        p->u_background = glGetUniformLocation(p->id, "background");
        p->u_unshadowed = glGetUniformLocation(p->id, "unshadowed");
    }
    r->max_vertices = max_vertices;
    r->max_indices = max_indices;
    r->max_line_vertices = max_line_vertices;

    glGenVertexArrays(1, &r->vao);
    glBindVertexArray(r->vao);
    glGenBuffers(1, &r->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)max_vertices * sizeof(render_vertex)), NULL,
                 GL_STREAM_DRAW);
    set_vertex_layout();
    glGenBuffers(1, &r->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)((size_t)max_indices * sizeof(unsigned)),
                 NULL, GL_STREAM_DRAW);

    glGenVertexArrays(1, &r->line_vao);
    glBindVertexArray(r->line_vao);
    glGenBuffers(1, &r->line_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, r->line_vbo);
    glBufferData(GL_ARRAY_BUFFER,
                 (GLsizeiptr)((size_t)(max_line_vertices > 0 ? max_line_vertices : 1) *
                              sizeof(render_vertex)),
                 NULL, GL_STATIC_DRAW);
    set_vertex_layout();
    glBindVertexArray(0);
    if (glGetError() != GL_NO_ERROR) {
        snprintf(err, errlen, "gl: cannot create the vertex buffers");
        gl_renderer_destroy(r);
        return NULL;
    }
    return r;
}

void gl_renderer_destroy(gl_renderer *r)
{
    if (!r) return;
    /* its objects belong to its context (another view's may be current) */
    if (r->context) gl_context_make_current(r->context);
    if (r->receiver_vao) glDeleteVertexArrays(1, &r->receiver_vao);
    if (r->receiver_vbo) glDeleteBuffers(1, &r->receiver_vbo);
    if (r->receiver_ibo) glDeleteBuffers(1, &r->receiver_ibo);
    if (r->shadow_fbo) glDeleteFramebuffers(1, &r->shadow_fbo);
    if (r->shadow_texture) glDeleteTextures(1, &r->shadow_texture);
    if (r->shadow_program) glDeleteProgram(r->shadow_program);
    if (r->cache_fbo) glDeleteFramebuffers(1, &r->cache_fbo);
    if (r->cache_color) glDeleteRenderbuffers(1, &r->cache_color);
    if (r->cache_depth) glDeleteRenderbuffers(1, &r->cache_depth);
    if (r->cache_look_up) glDeleteTextures(1, &r->cache_look_up);
    if (r->cache_key) glDeleteTextures(1, &r->cache_key);
    if (r->vao) glDeleteVertexArrays(1, &r->vao);
    if (r->line_vao) glDeleteVertexArrays(1, &r->line_vao);
    if (r->vbo) glDeleteBuffers(1, &r->vbo);
    if (r->ibo) glDeleteBuffers(1, &r->ibo);
    if (r->line_vbo) glDeleteBuffers(1, &r->line_vbo);
    for (int v = 0; v < SHADE_VARIANTS; v++)
        if (r->programs[v].id) glDeleteProgram(r->programs[v].id);
    gl_target_destroy(r->target);
    gl_context_destroy(r->context);
    free(r->box_pixels);
    free(r->look_ups);
    free(r->key_colors);
    free(r->map);
    free(r->block_least);
    free(r->block_lit);
    free(r->tiles);
    free(r);
}

int gl_renderer_set_samples(gl_renderer *r, int samples, char *err, size_t errlen)
{
    if (gl_context_make_current(r->context)) {
        snprintf(err, errlen, "gl: cannot make the context current");
        return -1;
    }
    gl_target *target = gl_target_create(r->width, r->height, samples, err, errlen);
    if (!target) return -1;
    gl_target_destroy(r->target);
    r->target = target;
    return 0;
}

const char *gl_renderer_description(const gl_renderer *r)
{
    return gl_context_description(r->context);
}

void gl_renderer_set_lines(gl_renderer *r, const render_vertex *lines, int count)
{
    if (gl_context_make_current(r->context)) return;
    if (count > r->max_line_vertices) count = r->max_line_vertices;
    glBindBuffer(GL_ARRAY_BUFFER, r->line_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)((size_t)count * sizeof(render_vertex)), lines);
    r->line_count = count;
}

static void normalized(float out[3], double x, double y, double z)
{
    double n = sqrt(x * x + y * y + z * z);
    out[0] = (float)(x / n);
    out[1] = (float)(y / n);
    out[2] = (float)(z / n);
}

static void set_camera(gl_renderer *r, const render_camera *cam)
{
    glEnable(GL_DEPTH_TEST);
    /* Back faces are culled: every surface is closed and wound outward
     * (mesh.c: mesh_triangle); the stripe band lies on the tube, so its
     * back is inside. The shader still lights both sides. */
    glEnable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    float matrix[16];
    for (int i = 0; i < 16; i++) matrix[i] = (float)cam->view_projection[i];
    /* Lights ride with the camera: the key from upper left in front
     * (render_key_light, which the shadows use too), the fill from the
     * right, so the picture reads the same from any view. */
    float key[3], fill[3];
    const double *d = cam->direction, *u = cam->up, *rt = cam->right;
    double key_direction[3];
    render_key_light(cam, key_direction);
    normalized(key, key_direction[0], key_direction[1], key_direction[2]);
    normalized(fill, 0.5 * d[0] - 0.2 * u[0] + 0.9 * rt[0], 0.5 * d[1] - 0.2 * u[1] + 0.9 * rt[1],
               0.5 * d[2] - 0.2 * u[2] + 0.9 * rt[2]);
    if (r->shadow_size > 0) {
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, r->shadow_texture);
        glActiveTexture(GL_TEXTURE0);
    }
    for (int v = 0; v < SHADE_VARIANTS; v++) {
        const scene_program *p = &r->programs[v];
        glUseProgram(p->id);
        glUniformMatrix4fv(p->u_view_projection, 1, GL_FALSE, matrix);
        glUniform1i(p->u_orthographic, cam->orthographic);
        glUniform3f(p->u_eye, (float)cam->eye[0], (float)cam->eye[1], (float)cam->eye[2]);
        glUniform3f(p->u_view_direction, (float)cam->direction[0], (float)cam->direction[1],
                    (float)cam->direction[2]);
        glUniform3fv(p->u_key, 1, key);
        glUniform3fv(p->u_fill, 1, fill);
        glUniform1i(p->u_shadows, r->shadow_size > 0);
        if (r->shadow_size > 0) {
            glUniform1i(p->u_shadow_map, 1);
            glUniformMatrix4fv(p->u_light, 1, GL_FALSE, r->light);
            glUniform1f(p->u_shadow_offset, r->shadow_offset);
            glUniform4fv(p->u_unshadowed, 1, r->unshadowed);
        }
    }
}

/* Draws with shading variant v from now on. */
static void use_shading(const gl_renderer *r, int v)
{
    glUseProgram(r->programs[v].id);
}

int gl_renderer_set_receivers(gl_renderer *r, const render_vertex *vertices, int vertex_count,
                              const unsigned *indices, int plane_index_count, int index_count,
                              const double fade[5], const unsigned char background[3])
{
    if (gl_context_make_current(r->context)) return -1;
    if (!r->receiver_vao) {
        glGenVertexArrays(1, &r->receiver_vao);
        glGenBuffers(1, &r->receiver_vbo);
        glGenBuffers(1, &r->receiver_ibo);
    }
    glBindVertexArray(r->receiver_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->receiver_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)(vertex_count > 0 ? vertex_count : 1) *
                                               sizeof(render_vertex)),
                 vertices, GL_STATIC_DRAW);
    set_vertex_layout();
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->receiver_ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 (GLsizeiptr)((size_t)(index_count > 0 ? index_count : 1) * sizeof(unsigned)),
                 indices, GL_STATIC_DRAW);
    glBindVertexArray(0);
    r->receiver_plane_indices = plane_index_count;
    r->receiver_indices = index_count;
    for (int k = 0; k < 4; k++) r->fade[k] = (float)fade[k];
    r->fade_end = (float)fade[4];
    for (int k = 0; k < 3; k++) r->background_rgb[k] = background[k] / 255.0f;
    r->cache_valid = 0;
    for (int v = 0; v < SHADE_VARIANTS; v++) {
        glUseProgram(r->programs[v].id);
        glUniform3fv(r->programs[v].u_background, 1, r->background_rgb);
        glUniform4fv(r->programs[v].u_fade, 1, r->fade);
        glUniform1f(r->programs[v].u_fade_end, r->fade_end);
    }
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

void gl_renderer_set_unshadowed(gl_renderer *r, const double normal[3])
{
    for (int c = 0; c < 3; c++) r->unshadowed[c] = (float)normal[c];
    r->unshadowed[3] = 1.0f;
}

void gl_renderer_set_whole_boxes(gl_renderer *r, int whole, const unsigned char background[3])
{
    r->whole_boxes = whole;
    for (int k = 0; k < 3; k++) r->background_rgb[k] = background[k] / 255.0f;
}

int gl_renderer_set_shadows(gl_renderer *r, const double light_view_projection[16], int size,
                            double offset, char *err, size_t errlen)
{
    if (gl_context_make_current(r->context)) {
        snprintf(err, errlen, "gl: cannot make the context current");
        return -1;
    }
    if (!r->shadow_program) {
        r->shadow_program = gl_program_load("shadow", err, errlen);
        if (!r->shadow_program) return -1;
        r->u_shadow_light = glGetUniformLocation(r->shadow_program, "light_view_projection");
        glGenTextures(1, &r->shadow_texture);
        glBindTexture(GL_TEXTURE_2D, r->shadow_texture);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, size, size, 0, GL_DEPTH_COMPONENT,
                     GL_UNSIGNED_INT, NULL);
        /* hardware PCF: each lookup compares and filters the 4 texels around it */
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        glBindTexture(GL_TEXTURE_2D, 0);
        glGenFramebuffers(1, &r->shadow_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, r->shadow_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, r->shadow_texture,
                               0);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
        GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (status != GL_FRAMEBUFFER_COMPLETE || glGetError() != GL_NO_ERROR) {
            snprintf(err, errlen, "gl: cannot make the %d x %d shadow map (status 0x%x)", size,
                     size, (unsigned)status);
            return -1;
        }
    }
    r->shadow_size = size;
    for (int k = 0; k < 16; k++) r->light[k] = (float)light_view_projection[k];
    r->shadow_offset = (float)offset;
    return 0;
}

/* The texels (x0, y0, x1, y1) that hold the shadow map's pixels of the
 * vertices, a texel of margin around: the casters' triangles lie inside. */
static void caster_texels(const gl_renderer *r, const render_vertex *vertices, int count,
                          int texels[4])
{
    const float *m = r->light; /* column-major; orthographic: w = 1 */
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    for (int i = 0; i < count; i++) {
        const float *p = vertices[i].position;
        for (int a = 0; a < 2; a++) {
            float c = m[a] * p[0] + m[4 + a] * p[1] + m[8 + a] * p[2] + m[12 + a];
            lo[a] = c < lo[a] ? c : lo[a];
            hi[a] = c > hi[a] ? c : hi[a];
        }
    }
    for (int a = 0; a < 2; a++) {
        double from = floor((0.5 * lo[a] + 0.5) * r->shadow_size) - 2;
        double to = ceil((0.5 * hi[a] + 0.5) * r->shadow_size) + 2;
        texels[a] = (int)fmax(0, fmin(r->shadow_size, from));
        texels[2 + a] = (int)fmax(0, fmin(r->shadow_size, to));
    }
}

/* The depth pass: the first caster_indices indices of the frame's
 * triangles (0: an empty map, nothing casts) into the shadow map. Only
 * the texels the casters may cover, now or in the pass before, are
 * cleared and drawn (the map's clear was a fixed cost of every frame);
 * the rest stays cleared. vertices: the frame's, NULL: the whole map. */
static void draw_shadow_map(gl_renderer *r, int caster_indices, const render_vertex *vertices,
                            int vertex_count)
{
    glBindFramebuffer(GL_FRAMEBUFFER, r->shadow_fbo);
    glViewport(0, 0, r->shadow_size, r->shadow_size);
    glEnable(GL_DEPTH_TEST);
    int now[4] = {0, 0, 0, 0};
    if (vertices && caster_indices > 0) caster_texels(r, vertices, vertex_count, now);
    int *was = r->shadow_drawn;
    if (!vertices) {
        glDisable(GL_SCISSOR_TEST);
    } else {
        /* the union of what was drawn and what will be */
        int box[4];
        for (int a = 0; a < 2; a++) {
            int empty_now = now[0] >= now[2] || now[1] >= now[3];
            int empty_was = was[0] >= was[2] || was[1] >= was[3];
            box[a] = empty_now ? was[a] : empty_was ? now[a] : (now[a] < was[a] ? now[a] : was[a]);
            box[2 + a] = empty_now ? was[2 + a]
                         : empty_was ? now[2 + a]
                                     : (now[2 + a] > was[2 + a] ? now[2 + a] : was[2 + a]);
        }
        glEnable(GL_SCISSOR_TEST);
        glScissor(box[0], box[1], box[2] > box[0] ? box[2] - box[0] : 0,
                  box[3] > box[1] ? box[3] - box[1] : 0);
    }
    glClear(GL_DEPTH_BUFFER_BIT);
    for (int k = 0; k < 4; k++) was[k] = now[k];
    if (caster_indices > 0) {
        /* the casters' far sides: the lit side of the tube compares against
         * the side away from the light, so it does not shadow itself */
        glEnable(GL_CULL_FACE);
        glCullFace(GL_FRONT);
        glUseProgram(r->shadow_program);
        glUniformMatrix4fv(r->u_shadow_light, 1, GL_FALSE, r->light);
        glBindVertexArray(r->vao);
        glDrawElements(GL_TRIANGLES, caster_indices, GL_UNSIGNED_INT, NULL);
        glBindVertexArray(0);
        glCullFace(GL_BACK);
    }
    glDisable(GL_SCISSOR_TEST);
}

/* The static receivers, inside the scissor box set: the solids, then the
 * planes (faded) behind them, whose hidden pixels the depth test then
 * drops before they are shaded (llvmpipe tests depth first). */
static void draw_receivers(gl_renderer *r, int cached)
{
    if (r->receiver_indices <= 0) return;
    glBindVertexArray(r->receiver_vao);
    use_shading(r, cached ? SHADE_MATTE_CACHED : SHADE_MATTE);
    if (r->receiver_indices > r->receiver_plane_indices)
        glDrawElements(GL_TRIANGLES, r->receiver_indices - r->receiver_plane_indices,
                       GL_UNSIGNED_INT,
                       (const void *)((size_t)r->receiver_plane_indices * sizeof(unsigned)));
    if (r->receiver_plane_indices > 0) {
        use_shading(r, cached ? SHADE_MATTE_FADED_CACHED : SHADE_MATTE_FADED);
        glDrawElements(GL_TRIANGLES, r->receiver_plane_indices, GL_UNSIGNED_INT, NULL);
    }
    glBindVertexArray(0);
}

int gl_renderer_draw_backdrop(gl_renderer *r, const render_camera *cam,
                              const unsigned char background[3], image *out)
{
    if (gl_context_make_current(r->context)) return -1;
    if (r->shadow_size > 0) draw_shadow_map(r, 0, NULL, 0); /* nothing casts on the backdrop */
    gl_target_bind(r->target);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(background[0] / 255.0f, background[1] / 255.0f, background[2] / 255.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    set_camera(r, cam);
    if (r->line_count > 0) {
        use_shading(r, SHADE_FLAT);
        glBindVertexArray(r->line_vao);
        glDrawArrays(GL_LINES, 0, r->line_count);
        glBindVertexArray(0);
    }
    draw_receivers(r, 0);
    return gl_target_read(r->target, out);
}

/* A texture of the picture's size (format internal), nearest texels, for texelFetch. */
static GLuint cache_texture(const gl_renderer *r, GLenum internal, GLenum type)
{
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, r->width, r->height, 0, GL_RGBA, type, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    return t;
}

/* The receivers' cache's framebuffer and its CPU copies, made once. 0, or
 * -1 (then boxes are drawn whole, as without the cache). */
static int cache_create(gl_renderer *r)
{
    if (r->cache_fbo) return 0;
    const size_t pixels = (size_t)r->width * (size_t)r->height;
    r->look_ups = malloc(pixels * sizeof *r->look_ups);
    r->key_colors = malloc(pixels * 3 * sizeof(unsigned short));
    r->tiles_x = (r->width + DARKEN_TILE - 1) / DARKEN_TILE;
    r->tiles_y = (r->height + DARKEN_TILE - 1) / DARKEN_TILE;
    r->tiles = malloc((size_t)r->tiles_x * (size_t)r->tiles_y * sizeof *r->tiles);
    if (!r->look_ups || !r->key_colors || !r->tiles) return -1;
    glGenFramebuffers(1, &r->cache_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, r->cache_fbo);
    /* depth as the target's, so that a box's is a plain copy */
    glGenRenderbuffers(1, &r->cache_color);
    glBindRenderbuffer(GL_RENDERBUFFER, r->cache_color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, r->width, r->height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              r->cache_color);
    glGenRenderbuffers(1, &r->cache_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, r->cache_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, r->width, r->height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->cache_depth);
    r->cache_look_up = cache_texture(r, GL_RGBA32F, GL_FLOAT);
    r->cache_key = cache_texture(r, GL_RGBA32F, GL_FLOAT);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, r->cache_look_up,
                           0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT2, GL_TEXTURE_2D, r->cache_key, 0);
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(3, buffers);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return status == GL_FRAMEBUFFER_COMPLETE && glGetError() == GL_NO_ERROR ? 0 : -1;
}

/* The look-up of the shadow map's coordinates c (xyz; w 0: none), as
 * scene.frag's key_visibility makes it with GL_LINEAR and clamping to the
 * edge on a map of n texels a side. */
static map_look_up look_up_of(const float *c, int n)
{
    map_look_up m = {0, LOOK_UP_NONE, 0, 0, 0};
    if (c[3] == 0.0f || c[0] < 0.0f || c[0] > 1.0f || c[1] < 0.0f || c[1] > 1.0f) return m;
    const float s = c[0] * (float)n - 0.5f, t = c[1] * (float)n - 0.5f;
    const int i = (int)floorf(s), j = (int)floorf(t);
    /* before the first texel: both columns (rows) the first, its weight 0 */
    m.i0 = (unsigned short)(i < 0 ? 0 : i);
    m.j0 = (unsigned short)(j < 0 ? 0 : j);
    m.wx = (unsigned char)(i < 0 ? 0 : (s - (float)i) * 255.0f + 0.5f);
    m.wy = (unsigned char)(j < 0 ? 0 : (t - (float)j) * 255.0f + 0.5f);
    const float ref = c[2] < 0.0f ? 0.0f : c[2] > 1.0f ? 1.0f : c[2];
    m.ref = (unsigned short)(ref * 65535.0f + 0.5f);
    return m;
}

/* The cache's look-ups and key colours read into r's CPU copies (through
 * a scratch of 4 floats a pixel). 0, or -1. */
static int cache_read(gl_renderer *r)
{
    const size_t pixels = (size_t)r->width * (size_t)r->height;
    float *scratch = malloc(pixels * 4 * sizeof(float));
    if (!scratch) return -1;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->cache_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, r->width, r->height, GL_RGBA, GL_FLOAT, scratch);
    for (size_t i = 0; i < pixels; i++)
        r->look_ups[i] = r->shadow_size > 0 ? look_up_of(&scratch[4 * i], r->shadow_size)
                                            : (map_look_up){0, LOOK_UP_NONE, 0, 0, 0};
    for (int t = 0; t < r->tiles_x * r->tiles_y; t++)
        r->tiles[t] = (tile_reach){0xffff, 0, 0xffff, 0, 0};
    for (int y = 0; y < r->height; y++)
        for (int x = 0; x < r->width; x++) {
            const map_look_up *m = &r->look_ups[(size_t)y * (size_t)r->width + (size_t)x];
            if (m->j0 == LOOK_UP_NONE) continue;
            tile_reach *t = &r->tiles[(y / DARKEN_TILE) * r->tiles_x + x / DARKEN_TILE];
            const unsigned short bx = m->i0 / MAP_BLOCK, by = m->j0 / MAP_BLOCK;
            t->bx0 = bx < t->bx0 ? bx : t->bx0;
            t->bx1 = bx > t->bx1 ? bx : t->bx1;
            t->by0 = by < t->by0 ? by : t->by0;
            t->by1 = by > t->by1 ? by : t->by1;
            t->ref = m->ref > t->ref ? m->ref : t->ref;
        }
    glReadBuffer(GL_COLOR_ATTACHMENT2);
    glReadPixels(0, 0, r->width, r->height, GL_RGBA, GL_FLOAT, scratch);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++) {
            /* 1/256 of a level */
            float k = scratch[4 * i + c] * 255.0f * 256.0f + 0.5f;
            r->key_colors[3 * i + c] = (unsigned short)(k < 0 ? 0 : k > 65535 ? 65535 : k);
        }
    free(scratch);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

/* The receivers' cache for this camera and light (set_camera done): drawn
 * unless it already holds them. 0, or -1 when it cannot be made (then
 * never tried again); the target bound either way. */
static int receiver_cache(gl_renderer *r, const render_camera *cam)
{
    float camera[16];
    for (int i = 0; i < 16; i++) camera[i] = (float)cam->view_projection[i];
    if (r->cache_valid && !memcmp(camera, r->cache_camera, sizeof camera) &&
        !memcmp(r->light, r->cache_light, sizeof r->light) && r->shadow_offset == r->cache_offset)
        return 0;
    if (r->cache_failed || cache_create(r)) {
        r->cache_failed = 1;
        gl_target_bind(r->target);
        return -1;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, r->cache_fbo);
    glViewport(0, 0, r->width, r->height);
    glDisable(GL_SCISSOR_TEST);
    const float background[4] = {r->background_rgb[0], r->background_rgb[1],
                                 r->background_rgb[2], 1};
    const float none[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, background);
    glClearBufferfv(GL_COLOR, 1, none);
    glClearBufferfv(GL_COLOR, 2, none);
    glClear(GL_DEPTH_BUFFER_BIT);
    if (r->line_count > 0) {
        use_shading(r, SHADE_FLAT_CACHED);
        glBindVertexArray(r->line_vao);
        glDrawArrays(GL_LINES, 0, r->line_count);
        glBindVertexArray(0);
    }
    draw_receivers(r, 1);
    const int read = cache_read(r);
    gl_target_bind(r->target);
    if (read) {
        r->cache_failed = 1;
        return -1;
    }
    memcpy(r->cache_camera, camera, sizeof camera);
    memcpy(r->cache_light, r->light, sizeof r->light);
    r->cache_offset = r->shadow_offset;
    r->cache_valid = 1;
    return 0;
}

/* The boxes from the receivers' cache: transparent, their depth copied
 * (no scissor: a plain copy), so that the receivers hide what they should. */
static void boxes_from_cache(gl_renderer *r, const render_camera *cam, const int *boxes,
                             int box_count)
{
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->cache_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl_target_framebuffer(r->target));
    for (int b = 0; b < box_count; b++) {
        const int *box = &boxes[4 * b];
        const int y0 = cam->height - (box[1] + box[3]), y1 = cam->height - box[1];
        glBlitFramebuffer(box[0], y0, box[0] + box[2], y1, box[0], y0, box[0] + box[2], y1,
                          GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    }
    gl_target_bind(r->target);
    glClearColor(0, 0, 0, 0);
    glEnable(GL_SCISSOR_TEST);
    for (int b = 0; b < box_count; b++) {
        const int *box = &boxes[4 * b];
        glScissor(box[0], cam->height - (box[1] + box[3]), box[2], box[3]);
        glClear(GL_COLOR_BUFFER_BIT);
    }
    glDisable(GL_SCISSOR_TEST);
}

/* Each block's least depth (r->block_least) over its texels and those of
 * the column and row after it (a look-up's second texels), from r->map;
 * 1 outside the texels read (cleared). */
static void block_least(gl_renderer *r)
{
    const int n = r->shadow_size, *read = r->map_read;
    for (int i = 0; i < r->blocks * r->blocks; i++) r->block_least[i] = 1.0f;
    for (int y = read[1]; y < read[3]; y++) {
        const float *row = &r->map[(size_t)y * (size_t)n];
        for (int x = read[0]; x < read[2]; x++) {
            if (row[x] >= 1.0f) continue;
            /* the blocks whose look-ups can reach texel (x, y): its own, and
             * those before it when it starts a column or row of blocks */
            for (int by = y / MAP_BLOCK; by >= 0 && by >= (y - 1) / MAP_BLOCK; by--)
                for (int bx = x / MAP_BLOCK; bx >= 0 && bx >= (x - 1) / MAP_BLOCK; bx--) {
                    float *least = &r->block_least[by * r->blocks + bx];
                    if (row[x] < *least) *least = row[x];
                }
        }
    }
    /* a look-up's ref / 65535 <= least */
    for (int i = 0; i < r->blocks * r->blocks; i++)
        r->block_lit[i] = (unsigned short)floorf(r->block_least[i] * 65535.0f);
}

/* The shadow map's texels the last depth pass drew (r->shadow_drawn) read
 * into r->map, the texels read before and not now set to 1 (cleared). 0,
 * or -1 on a GL error. */
static int map_read(gl_renderer *r)
{
    const int n = r->shadow_size;
    if (!r->map) {
        r->blocks = (n + MAP_BLOCK - 1) / MAP_BLOCK;
        r->map = malloc((size_t)n * (size_t)n * sizeof(float));
        r->block_least = malloc((size_t)r->blocks * (size_t)r->blocks * sizeof(float));
        r->block_lit = malloc((size_t)r->blocks * (size_t)r->blocks * sizeof(unsigned short));
        if (!r->map || !r->block_least || !r->block_lit) return -1;
        for (size_t i = 0; i < (size_t)n * (size_t)n; i++) r->map[i] = 1.0f;
        for (int i = 0; i < r->blocks * r->blocks; i++) r->block_least[i] = 1.0f;
    }
    int *was = r->map_read;
    for (int y = was[1]; y < was[3]; y++)
        for (int x = was[0]; x < was[2]; x++) r->map[(size_t)y * (size_t)n + (size_t)x] = 1.0f;
    const int *now = r->shadow_drawn;
    for (int k = 0; k < 4; k++) was[k] = now[k];
    if (now[0] >= now[2] || now[1] >= now[3]) return 0;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->shadow_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, n);
    glReadPixels(now[0], now[1], now[2] - now[0], now[3] - now[1], GL_DEPTH_COMPONENT, GL_FLOAT,
                 &r->map[(size_t)now[1] * (size_t)n + (size_t)now[0]]);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    gl_target_bind(r->target);
    block_least(r);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

/* The key light reaching a receiver's pixel of look-up m (scene.frag's
 * key_visibility: one bilinear comparison, GL_LEQUAL) against r->map. */
static float map_visibility(const gl_renderer *r, const map_look_up *m)
{
    const float ref = m->ref * (1.0f / 65535.0f);
    const int n = r->shadow_size;
    const int i1 = m->i0 + 1 < n ? m->i0 + 1 : n - 1, j1 = m->j0 + 1 < n ? m->j0 + 1 : n - 1;
    const float *row0 = &r->map[(size_t)m->j0 * (size_t)n], *row1 = &r->map[(size_t)j1 * (size_t)n];
    const float a = ref <= row0[m->i0], b = ref <= row0[i1];
    const float c = ref <= row1[m->i0], d = ref <= row1[i1];
    const float fx = m->wx * (1.0f / 255.0f), fy = m->wy * (1.0f / 255.0f);
    return (1 - fy) * ((1 - fx) * a + fx * b) + fy * ((1 - fx) * c + fx * d);
}

/* Whether every look-up of tile t is lit: its blocks hold nothing nearer
 * the light than its largest depth compared. */
static int tile_lit(const gl_renderer *r, const tile_reach *t)
{
    for (int by = t->by0; by <= t->by1; by++)
        for (int bx = t->bx0; bx <= t->bx1; bx++)
            if (t->ref > r->block_lit[by * r->blocks + bx]) return 0;
    return 1; /* also no look-up: bx0 > bx1 */
}

/* Darkens the pixels x0 <= x < x1, y0 <= y < y1 (GL's, bottom-up) of out. */
static void darken_rect(const gl_renderer *r, int x0, int y0, int x1, int y1, image *out)
{
    for (int y = y0; y < y1; y++) {
        const size_t row = (size_t)y * (size_t)r->width;
        unsigned char *dst =
            out->rgb + ((size_t)(r->height - 1 - y) * (size_t)out->width + (size_t)x0) * 3;
        for (int x = x0; x < x1; x++, dst += 3) {
            const map_look_up *m = &r->look_ups[row + (size_t)x];
            /* no look-up, or nothing nearer the light in its block: lit */
            if (m->j0 == LOOK_UP_NONE ||
                m->ref <= r->block_lit[(m->j0 / MAP_BLOCK) * r->blocks + m->i0 / MAP_BLOCK])
                continue;
            const float shade = 1.0f - map_visibility(r, m);
            if (shade <= 0.0f) continue;
            const unsigned short *key = &r->key_colors[3 * (row + (size_t)x)];
            for (int k = 0; k < 3; k++) {
                /* in 1/256 of a level, rounded */
                int v = dst[k] * 256 - (int)(shade * (float)key[k]) + 128;
                dst[k] = (unsigned char)(v < 0 ? 0 : v >> 8);
            }
        }
    }
}

int gl_renderer_darken(const gl_renderer *r, const int *boxes, int box_count, image *out)
{
    if (!r->cached) return 0;
    if (r->shadow_size <= 0) return 1;
    for (int b = 0; b < box_count; b++) {
        const int *box = &boxes[4 * b];
        /* GL's rows, bottom-up */
        const int x0 = box[0], x1 = box[0] + box[2];
        const int y0 = r->height - (box[1] + box[3]), y1 = r->height - box[1];
        for (int ty = y0 / DARKEN_TILE; ty * DARKEN_TILE < y1; ty++)
            for (int tx = x0 / DARKEN_TILE; tx * DARKEN_TILE < x1; tx++) {
                if (tile_lit(r, &r->tiles[ty * r->tiles_x + tx])) continue;
                const int ax = tx * DARKEN_TILE, ay = ty * DARKEN_TILE;
                darken_rect(r, ax > x0 ? ax : x0, ay > y0 ? ay : y0,
                            ax + DARKEN_TILE < x1 ? ax + DARKEN_TILE : x1,
                            ay + DARKEN_TILE < y1 ? ay + DARKEN_TILE : y1, out);
            }
    }
    return 1;
}

const unsigned char *gl_renderer_draw_boxes(gl_renderer *r, const render_camera *cam,
                                            const render_vertex *vertices, int vertex_count,
                                            const unsigned *indices, int index_count,
                                            int caster_index_count, const int *boxes,
                                            int box_count, const int *drawn_boxes,
                                            int drawn_box_count, int read_box[4],
                                            double *shadow_seconds)
{
    if (gl_context_make_current(r->context)) return NULL;
    if (vertex_count > r->max_vertices) vertex_count = r->max_vertices;
    if (index_count > r->max_indices) index_count = r->max_indices;
    if (caster_index_count > index_count) caster_index_count = index_count;
    glBindVertexArray(r->vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)((size_t)vertex_count * sizeof(render_vertex)),
                    vertices);
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, (GLsizeiptr)((size_t)index_count * sizeof(unsigned)),
                    indices);
    glBindVertexArray(0);
    if (r->shadow_size > 0) {
        double started = shadow_seconds ? wall_seconds() : 0;
        draw_shadow_map(r, caster_index_count, vertices, vertex_count);
        if (shadow_seconds) {
            /* llvmpipe draws when asked for the result: wait for it to time the pass */
            glFinish();
            *shadow_seconds += wall_seconds() - started;
        }
    }
    gl_target_bind(r->target);
    set_camera(r, cam);
    /* With receivers the boxes are drawn whole (background, grid, surfaces,
     * then the rod): the shadow changes them. Else they are cleared to
     * transparent and only the rod is composited over the backdrop. */
    int opaque = r->receiver_indices > 0 || r->whole_boxes;
    /* a still camera over receivers: the boxes from their cache (drawn once) */
    const int cached = r->receiver_indices > 0 && !r->whole_boxes &&
                       gl_target_samples(r->target) == 0 && receiver_cache(r, cam) == 0;
    r->cached = cached;
    if (cached) {
        /* the boxes a shadow only falls in are the backdrop's, darkened */
        boxes = drawn_boxes;
        box_count = drawn_box_count;
        boxes_from_cache(r, cam, boxes, box_count);
        if (r->shadow_size > 0 && map_read(r)) return NULL;
    }
    if (opaque)
        glClearColor(r->background_rgb[0], r->background_rgb[1], r->background_rgb[2], 1.0f);
    else
        glClearColor(0, 0, 0, 0);
    glEnable(GL_SCISSOR_TEST);
    for (int b = 0; !cached && b < box_count; b++) {
        const int *box = &boxes[4 * b];
        glScissor(box[0], cam->height - (box[1] + box[3]), box[2], box[3]);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        if (!opaque) continue;
        /* as the backdrop draws them, so that the box's edges do not show */
        if (r->line_count > 0) {
            use_shading(r, SHADE_FLAT);
            glBindVertexArray(r->line_vao);
            glDrawArrays(GL_LINES, 0, r->line_count);
            glBindVertexArray(0);
        }
        draw_receivers(r, 0);
    }
    glDisable(GL_SCISSOR_TEST);
    /* One draw for all boxes: the boxes cover the geometry by construction,
     * and whatever lands outside them is never resolved or read. */
    glBindVertexArray(r->vao);
    use_shading(r, SHADE_GLOSSY);
    if (caster_index_count > 0)
        glDrawElements(GL_TRIANGLES, caster_index_count, GL_UNSIGNED_INT, NULL);
    if (index_count > caster_index_count) {
        /* the punctures: matte marks on the surfaces */
        use_shading(r, SHADE_MATTE);
        glDrawElements(GL_TRIANGLES, index_count - caster_index_count, GL_UNSIGNED_INT,
                       (const void *)((size_t)caster_index_count * sizeof(unsigned)));
    }
    glBindVertexArray(0);
    /* resolve each box, then read their bounding rectangle at once */
    int lo_x = cam->width, lo_y = cam->height, hi_x = 0, hi_y = 0;
    for (int b = 0; b < box_count; b++) {
        const int *box = &boxes[4 * b];
        if (gl_target_resolve_box(r->target, box[0], box[1], box[2], box[3])) return NULL;
        lo_x = box[0] < lo_x ? box[0] : lo_x;
        lo_y = box[1] < lo_y ? box[1] : lo_y;
        hi_x = box[0] + box[2] > hi_x ? box[0] + box[2] : hi_x;
        hi_y = box[1] + box[3] > hi_y ? box[1] + box[3] : hi_y;
    }
    read_box[0] = lo_x;
    read_box[1] = lo_y;
    read_box[2] = hi_x - lo_x;
    read_box[3] = hi_y - lo_y;
    if (box_count > 0 &&
        gl_target_read_resolved_rgba(r->target, lo_x, lo_y, hi_x - lo_x, hi_y - lo_y, r->box_pixels))
        return NULL;
    return r->box_pixels;
}
