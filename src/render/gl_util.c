/* gl_util.c: shader programs and offscreen targets (see gl_util.h). */
#include "render/gl_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/embedded.h"
#include "render/gl_api.h"

/* The shaders are compiled into the binary (base/embedded.h), so it renders
 * wherever it is installed. For shader development, RODSIM_SHADER_DIR=dir
 * reads dir/NAME.vert and dir/NAME.frag instead, at every program load:
 * edit shaders/ and rerun, without rebuilding. */
static char *read_text_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    char *text = NULL;
    if (fseek(fp, 0, SEEK_END) == 0) {
        long size = ftell(fp);
        if (size >= 0 && fseek(fp, 0, SEEK_SET) == 0 && (text = malloc((size_t)size + 1))) {
            if (fread(text, 1, (size_t)size, fp) != (size_t)size) {
                free(text);
                text = NULL;
            } else {
                text[size] = '\0';
            }
        }
    }
    fclose(fp);
    return text;
}

/* The source of shader file `file` ("scene.vert"), into *path a name for
 * messages; free it with free(). NULL with a message when there is none. */
static char *shader_source(const char *file, char *path, size_t pathlen, char *err, size_t errlen)
{
    const char *dir = getenv("RODSIM_SHADER_DIR");
    if (dir && *dir) {
        snprintf(path, pathlen, "%s/%s", dir, file);
        char *text = read_text_file(path);
        if (!text) snprintf(err, errlen, "%s: cannot read shader (from RODSIM_SHADER_DIR)", path);
        return text;
    }
    snprintf(path, pathlen, "shaders/%s", file);
    const char *text = embedded_text(path);
    char *copy = text ? malloc(strlen(text) + 1) : NULL;
    if (!copy) {
        snprintf(err, errlen, text ? "gl: out of memory" : "%s: no such shader in the binary",
                 path);
        return NULL;
    }
    return strcpy(copy, text);
}

static GLuint compile_shader(GLenum kind, const char *file, const char *defines, char *path,
                             size_t pathlen, char *err, size_t errlen)
{
    char *source = shader_source(file, path, pathlen, err, errlen);
    if (!source) return 0;
    GLuint shader = glCreateShader(kind);
    /* the defines go after the #version line, which must come first */
    char *body = strchr(source, '\n');
    body = body ? body + 1 : source + strlen(source);
    const char *sources[3] = {source, defines ? defines : "", body};
    const GLint lengths[3] = {(GLint)(body - source), -1, -1};
    glShaderSource(shader, 3, sources, lengths);
    glCompileShader(shader);
    free(source);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetShaderInfoLog(shader, sizeof log, NULL, log);
        snprintf(err, errlen, "%s: GLSL compile error: %s", path, log);
        glDeleteShader(shader);
        return 0;
    }
    return shader;
}

unsigned gl_program_load(const char *name, char *err, size_t errlen)
{
    return gl_program_load_defined(name, NULL, err, errlen);
}

unsigned gl_program_load_defined(const char *name, const char *defines, char *err, size_t errlen)
{
    char vert_file[256], frag_file[256], vert_path[1200], frag_path[1200];
    snprintf(vert_file, sizeof vert_file, "%s.vert", name);
    snprintf(frag_file, sizeof frag_file, "%s.frag", name);
    GLuint vert = compile_shader(GL_VERTEX_SHADER, vert_file, defines, vert_path,
                                 sizeof vert_path, err, errlen);
    if (!vert) return 0;
    GLuint frag = compile_shader(GL_FRAGMENT_SHADER, frag_file, defines, frag_path,
                                 sizeof frag_path, err, errlen);
    if (!frag) {
        glDeleteShader(vert);
        return 0;
    }
    GLuint program = glCreateProgram();
    glAttachShader(program, vert);
    glAttachShader(program, frag);
    glLinkProgram(program);
    glDeleteShader(vert);
    glDeleteShader(frag);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetProgramInfoLog(program, sizeof log, NULL, log);
        snprintf(err, errlen, "%s + %s: GLSL link error: %s", vert_path, frag_path, log);
        glDeleteProgram(program);
        return 0;
    }
    return program;
}

struct gl_target {
    int width, height, samples;
    GLuint draw_fbo, draw_color, draw_depth; /* multisampled (or plain when samples == 0) */
    GLuint resolve_fbo, resolve_color;       /* single-sampled, for read-back */
    unsigned char *row;                      /* one row, for the vertical flip */
};

gl_target *gl_target_create(int width, int height, int samples, char *err, size_t errlen)
{
    gl_target *t = calloc(1, sizeof *t);
    if (!t || !(t->row = malloc((size_t)width * 3))) {
        free(t);
        snprintf(err, errlen, "gl: out of memory");
        return NULL;
    }
    GLint max_samples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    t->width = width;
    t->height = height;
    t->samples = samples <= 1 ? 0 : samples > max_samples ? max_samples : samples;

    glGenFramebuffers(1, &t->draw_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, t->draw_fbo);
    glGenRenderbuffers(1, &t->draw_color);
    glBindRenderbuffer(GL_RENDERBUFFER, t->draw_color);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, t->samples, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->draw_color);
    glGenRenderbuffers(1, &t->draw_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, t->draw_depth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, t->samples, GL_DEPTH_COMPONENT24, width,
                                     height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t->draw_depth);
    GLenum draw_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);

    glGenFramebuffers(1, &t->resolve_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, t->resolve_fbo);
    glGenRenderbuffers(1, &t->resolve_color);
    glBindRenderbuffer(GL_RENDERBUFFER, t->resolve_color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              t->resolve_color);
    GLenum resolve_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (draw_status != GL_FRAMEBUFFER_COMPLETE || resolve_status != GL_FRAMEBUFFER_COMPLETE) {
        snprintf(err, errlen, "gl: offscreen framebuffer %dx%d with %d samples is incomplete "
                              "(status 0x%x, 0x%x)", width, height, t->samples,
                 draw_status, resolve_status);
        gl_target_destroy(t);
        return NULL;
    }
    return t;
}

void gl_target_destroy(gl_target *t)
{
    if (!t) return;
    glDeleteFramebuffers(1, &t->draw_fbo);
    glDeleteFramebuffers(1, &t->resolve_fbo);
    glDeleteRenderbuffers(1, &t->draw_color);
    glDeleteRenderbuffers(1, &t->draw_depth);
    glDeleteRenderbuffers(1, &t->resolve_color);
    free(t->row);
    free(t);
}

void gl_target_bind(gl_target *t)
{
    glBindFramebuffer(GL_FRAMEBUFFER, t->draw_fbo);
    glViewport(0, 0, t->width, t->height);
}

int gl_target_samples(const gl_target *t) { return t->samples; }

unsigned gl_target_framebuffer(const gl_target *t) { return t->draw_fbo; }

int gl_target_read(gl_target *t, image *out)
{
    if (out->width != t->width || out->height != t->height) return -1;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->draw_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->resolve_fbo);
    glBlitFramebuffer(0, 0, t->width, t->height, 0, 0, t->width, t->height, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->resolve_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t->width, t->height, GL_RGB, GL_UNSIGNED_BYTE, out->rgb);
    glBindFramebuffer(GL_FRAMEBUFFER, t->draw_fbo);
    /* GL rows run bottom-up; images run top-down */
    size_t stride = (size_t)t->width * 3;
    for (int top = 0, bottom = t->height - 1; top < bottom; top++, bottom--) {
        unsigned char *a = out->rgb + (size_t)top * stride, *b = out->rgb + (size_t)bottom * stride;
        memcpy(t->row, a, stride);
        memcpy(a, b, stride);
        memcpy(b, t->row, stride);
    }
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

int gl_target_read_box_rgba(gl_target *t, int x, int y, int width, int height,
                            unsigned char *rgba)
{
    /* resolve only the box (the scissor limits llvmpipe's blit), then read it */
    if (gl_target_resolve_box(t, x, y, width, height)) return -1;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->samples ? t->resolve_fbo : t->draw_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(x, t->height - (y + height), width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glBindFramebuffer(GL_FRAMEBUFFER, t->draw_fbo);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

int gl_target_resolve_box(gl_target *t, int x, int y, int width, int height)
{
    int gl_y = t->height - (y + height);
    if (x < 0 || gl_y < 0 || width <= 0 || height <= 0 || x + width > t->width ||
        y + height > t->height)
        return -1;
    if (t->samples == 0) return 0; /* nothing to resolve: read from where it was drawn */
    glEnable(GL_SCISSOR_TEST);
    glScissor(x, gl_y, width, height);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->draw_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->resolve_fbo);
    glBlitFramebuffer(x, gl_y, x + width, gl_y + height, x, gl_y, x + width, gl_y + height,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, t->draw_fbo);
    return 0;
}

int gl_target_read_resolved_rgba(gl_target *t, int x, int y, int width, int height,
                                 unsigned char *rgba)
{
    int gl_y = t->height - (y + height);
    if (x < 0 || gl_y < 0 || width <= 0 || height <= 0 || x + width > t->width ||
        y + height > t->height)
        return -1;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->samples ? t->resolve_fbo : t->draw_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(x, gl_y, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glBindFramebuffer(GL_FRAMEBUFFER, t->draw_fbo);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}
