/* gl_plot.c: flat triangles in pixel space for the plot module (see gl_plot.h). */
#include "plot/gl_plot.h"

#include <stdio.h>
#include <stdlib.h>

#include "render/gl_api.h"
#include "render/gl_context.h"
#include "render/gl_util.h"

struct gl_plot {
    int width, height;
    gl_context *context;
    gl_target *target;
    GLuint program, vertex_array, vertex_buffer;
    GLint viewport_location, colour_location;
};

gl_plot *gl_plot_create(int width, int height, int samples, char *err, size_t errlen)
{
    gl_plot *g = calloc(1, sizeof *g);
    if (!g) {
        snprintf(err, errlen, "plot: out of memory");
        return NULL;
    }
    g->width = width;
    g->height = height;
    /* the default framebuffer is not drawn to: keep it small */
    if (!(g->context = gl_context_create(16, 16, err, errlen)) ||
        !(g->target = gl_target_create(width, height, samples, err, errlen)) ||
        !(g->program = gl_program_load("plot", err, errlen))) {
        gl_plot_destroy(g);
        return NULL;
    }
    g->viewport_location = glGetUniformLocation(g->program, "viewport_px");
    g->colour_location = glGetUniformLocation(g->program, "colour");
    glGenVertexArrays(1, &g->vertex_array);
    glBindVertexArray(g->vertex_array);
    glGenBuffers(1, &g->vertex_buffer);
    glBindBuffer(GL_ARRAY_BUFFER, g->vertex_buffer);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(0);
    gl_target_bind(g->target);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(g->program);
    glUniform2f(g->viewport_location, (float)width, (float)height);
    return g;
}

void gl_plot_destroy(gl_plot *g)
{
    if (!g) return;
    if (g->context) {
        if (g->vertex_buffer) glDeleteBuffers(1, &g->vertex_buffer);
        if (g->vertex_array) glDeleteVertexArrays(1, &g->vertex_array);
        if (g->program) glDeleteProgram(g->program);
        gl_target_destroy(g->target);
        gl_context_destroy(g->context);
    }
    free(g);
}

void gl_plot_clear(gl_plot *g, const unsigned char rgb[3])
{
    (void)g;
    glClearColor(rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
}

void gl_plot_clip(gl_plot *g, int left, int top, int right, int bottom)
{
    glEnable(GL_SCISSOR_TEST);
    glScissor(left, g->height - bottom, right - left, bottom - top); /* GL rows run bottom-up */
}

void gl_plot_clip_off(gl_plot *g)
{
    (void)g;
    glDisable(GL_SCISSOR_TEST);
}

void gl_plot_triangles(gl_plot *g, const float *xy, int vertex_count, const unsigned char rgb[3])
{
    if (vertex_count < 3) return;
    glUniform4f(g->colour_location, rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f, 1.0f);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)vertex_count * 2 * sizeof(float)), xy,
                 GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, vertex_count);
}

int gl_plot_read(gl_plot *g, image *out)
{
    glDisable(GL_SCISSOR_TEST);
    return gl_target_read(g->target, out);
}
