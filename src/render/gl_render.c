/* gl_render.c: the renderer's GL layer (see gl_render.h). */
#include "render/gl_render.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include "render/gl_api.h"
#include "render/gl_context.h"
#include "render/gl_util.h"

struct gl_renderer {
    gl_context *context;
    gl_target *target;
    GLuint program;
    GLuint vao, vbo, ibo;       /* per-frame triangles */
    GLuint line_vao, line_vbo;  /* static lines */
    int max_vertices, max_indices, max_line_vertices, line_count;
    unsigned char *box_pixels; /* (height x width x 4), RGBA of the last read rectangle */
    GLint u_view_projection, u_lit, u_orthographic, u_eye, u_view_direction, u_key, u_fill;
};

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
    r->target = gl_target_create(width, height, samples, err, errlen);
    r->program = r->target ? gl_program_load("scene", err, errlen) : 0;
    if (!r->target || !r->program) {
        gl_renderer_destroy(r);
        return NULL;
    }
    r->max_vertices = max_vertices;
    r->max_indices = max_indices;
    r->max_line_vertices = max_line_vertices;
    r->u_view_projection = glGetUniformLocation(r->program, "view_projection");
    r->u_lit = glGetUniformLocation(r->program, "lit");
    r->u_orthographic = glGetUniformLocation(r->program, "orthographic");
    r->u_eye = glGetUniformLocation(r->program, "eye");
    r->u_view_direction = glGetUniformLocation(r->program, "view_direction");
    r->u_key = glGetUniformLocation(r->program, "key_direction");
    r->u_fill = glGetUniformLocation(r->program, "fill_direction");

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
    if (r->vao) glDeleteVertexArrays(1, &r->vao);
    if (r->line_vao) glDeleteVertexArrays(1, &r->line_vao);
    if (r->vbo) glDeleteBuffers(1, &r->vbo);
    if (r->ibo) glDeleteBuffers(1, &r->ibo);
    if (r->line_vbo) glDeleteBuffers(1, &r->line_vbo);
    if (r->program) glDeleteProgram(r->program);
    gl_target_destroy(r->target);
    gl_context_destroy(r->context);
    free(r->box_pixels);
    free(r);
}

const char *gl_renderer_description(const gl_renderer *r)
{
    return gl_context_description(r->context);
}

void gl_renderer_set_lines(gl_renderer *r, const render_vertex *lines, int count)
{
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
     * (render.c add_triangle); the stripe band lies on the tube, so its
     * back is inside. The shader still lights both sides. */
    glEnable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    glUseProgram(r->program);
    float matrix[16];
    for (int i = 0; i < 16; i++) matrix[i] = (float)cam->view_projection[i];
    glUniformMatrix4fv(r->u_view_projection, 1, GL_FALSE, matrix);
    glUniform1i(r->u_orthographic, cam->orthographic);
    glUniform3f(r->u_eye, (float)cam->eye[0], (float)cam->eye[1], (float)cam->eye[2]);
    glUniform3f(r->u_view_direction, (float)cam->direction[0], (float)cam->direction[1],
                (float)cam->direction[2]);
    /* Lights ride with the camera: the key from upper left in front, the
     * fill from the right, so the picture reads the same from any view. */
    float key[3], fill[3];
    const double *d = cam->direction, *u = cam->up, *rt = cam->right;
    normalized(key, d[0] + 0.6 * u[0] - 0.5 * rt[0], d[1] + 0.6 * u[1] - 0.5 * rt[1],
               d[2] + 0.6 * u[2] - 0.5 * rt[2]);
    normalized(fill, 0.5 * d[0] - 0.2 * u[0] + 0.9 * rt[0], 0.5 * d[1] - 0.2 * u[1] + 0.9 * rt[1],
               0.5 * d[2] - 0.2 * u[2] + 0.9 * rt[2]);
    glUniform3fv(r->u_key, 1, key);
    glUniform3fv(r->u_fill, 1, fill);
}

int gl_renderer_draw_backdrop(gl_renderer *r, const render_camera *cam,
                              const unsigned char background[3], image *out)
{
    gl_target_bind(r->target);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(background[0] / 255.0f, background[1] / 255.0f, background[2] / 255.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    set_camera(r, cam);
    if (r->line_count > 0) {
        glUniform1i(r->u_lit, 0);
        glBindVertexArray(r->line_vao);
        glDrawArrays(GL_LINES, 0, r->line_count);
        glBindVertexArray(0);
    }
    return gl_target_read(r->target, out);
}

const unsigned char *gl_renderer_draw_boxes(gl_renderer *r, const render_camera *cam,
                                            const render_vertex *vertices, int vertex_count,
                                            const unsigned *indices, int index_count,
                                            const int *boxes, int box_count, int read_box[4])
{
    gl_target_bind(r->target);
    set_camera(r, cam);
    if (vertex_count > r->max_vertices) vertex_count = r->max_vertices;
    if (index_count > r->max_indices) index_count = r->max_indices;
    glUniform1i(r->u_lit, 1);
    glBindVertexArray(r->vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)((size_t)vertex_count * sizeof(render_vertex)),
                    vertices);
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, (GLsizeiptr)((size_t)index_count * sizeof(unsigned)),
                    indices);
    glClearColor(0, 0, 0, 0);
    glEnable(GL_SCISSOR_TEST);
    for (int b = 0; b < box_count; b++) {
        const int *box = &boxes[4 * b];
        glScissor(box[0], cam->height - (box[1] + box[3]), box[2], box[3]);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    glDisable(GL_SCISSOR_TEST);
    /* One draw for all boxes: the boxes cover the geometry by construction,
     * and whatever lands outside them is never resolved or read. */
    if (index_count > 0) glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, NULL);
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
