/* gl_api.h: the OpenGL functions the GL layer calls, as a table of pointers
 * filled at run time (gl_functions_load), so that the binary does not link
 * the GL library: OSMesa (with LLVM) costs ~40 ms to load and relocate at
 * every start, paid by `--help`, `--no-video` and FEM runs that never draw.
 * gl_context.c loads the library when the first context is made.
 *
 * Files that call GL include this header instead of <GL/gl.h>: it gives
 * the core-profile types and enums (<GL/glcorearb.h>, no prototypes) and
 * defines glXxx as the table's pointer, so call sites read as plain GL. A GL
 * function not in GL_FUNCTIONS is a compile error (no prototype) or a link
 * error, never a silent NULL call: add it to the list.
 *
 * Define GL_API_LOADER_ONLY before including to get only the loader (for
 * gl_context.c, which includes <GL/osmesa.h> and with it <GL/gl.h>, whose
 * declarations clash with glcorearb.h's). */
#ifndef RODSIM_GL_API_H
#define RODSIM_GL_API_H

#include <stddef.h>

typedef void (*gl_proc)(void);

/* Fills the table through get_proc (the context library's GetProcAddress;
 * NULL for a name it lacks). Call with a context current. 0, or -1 with a
 * message naming the first missing function. */
int gl_functions_load(gl_proc (*get_proc)(const char *name), char *err, size_t errlen);

#ifndef GL_API_LOADER_ONLY
#include <GL/glcorearb.h>

/* X(pointer type from glcorearb.h, name without the gl prefix) */
#define GL_FUNCTIONS(X) \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture) \
    X(PFNGLATTACHSHADERPROC, AttachShader) \
    X(PFNGLBINDBUFFERPROC, BindBuffer) \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer) \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer) \
    X(PFNGLBINDTEXTUREPROC, BindTexture) \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray) \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation) \
    X(PFNGLBLENDEQUATIONSEPARATEPROC, BlendEquationSeparate) \
    X(PFNGLBLENDFUNCPROC, BlendFunc) \
    X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer) \
    X(PFNGLBUFFERDATAPROC, BufferData) \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData) \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus) \
    X(PFNGLCLEARPROC, Clear) \
    X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv) \
    X(PFNGLCLEARCOLORPROC, ClearColor) \
    X(PFNGLCOMPILESHADERPROC, CompileShader) \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram) \
    X(PFNGLCREATESHADERPROC, CreateShader) \
    X(PFNGLCULLFACEPROC, CullFace) \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers) \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers) \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram) \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers) \
    X(PFNGLDELETESHADERPROC, DeleteShader) \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures) \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays) \
    X(PFNGLDEPTHMASKPROC, DepthMask) \
    X(PFNGLDISABLEPROC, Disable) \
    X(PFNGLDRAWARRAYSPROC, DrawArrays) \
    X(PFNGLDRAWBUFFERPROC, DrawBuffer) \
    X(PFNGLDRAWBUFFERSPROC, DrawBuffers) \
    X(PFNGLDRAWELEMENTSPROC, DrawElements) \
    X(PFNGLENABLEPROC, Enable) \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray) \
    X(PFNGLFINISHPROC, Finish) \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer) \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D) \
    X(PFNGLFRONTFACEPROC, FrontFace) \
    X(PFNGLGENBUFFERSPROC, GenBuffers) \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers) \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers) \
    X(PFNGLGENTEXTURESPROC, GenTextures) \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays) \
    X(PFNGLGETERRORPROC, GetError) \
    X(PFNGLGETINTEGERVPROC, GetIntegerv) \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog) \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv) \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog) \
    X(PFNGLGETSHADERIVPROC, GetShaderiv) \
    X(PFNGLGETSTRINGPROC, GetString) \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation) \
    X(PFNGLLINKPROGRAMPROC, LinkProgram) \
    X(PFNGLPIXELSTOREIPROC, PixelStorei) \
    X(PFNGLPOLYGONOFFSETPROC, PolygonOffset) \
    X(PFNGLREADBUFFERPROC, ReadBuffer) \
    X(PFNGLREADPIXELSPROC, ReadPixels) \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage) \
    X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, RenderbufferStorageMultisample) \
    X(PFNGLSCISSORPROC, Scissor) \
    X(PFNGLSHADERSOURCEPROC, ShaderSource) \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D) \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri) \
    X(PFNGLUNIFORM1FPROC, Uniform1f) \
    X(PFNGLUNIFORM1IPROC, Uniform1i) \
    X(PFNGLUNIFORM2FPROC, Uniform2f) \
    X(PFNGLUNIFORM3FPROC, Uniform3f) \
    X(PFNGLUNIFORM3FVPROC, Uniform3fv) \
    X(PFNGLUNIFORM4FPROC, Uniform4f) \
    X(PFNGLUNIFORM4FVPROC, Uniform4fv) \
    X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv) \
    X(PFNGLUSEPROGRAMPROC, UseProgram) \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer) \
    X(PFNGLVIEWPORTPROC, Viewport)

typedef struct gl_functions {
#define GL_FUNCTION_MEMBER(type, name) type name;
    GL_FUNCTIONS(GL_FUNCTION_MEMBER)
#undef GL_FUNCTION_MEMBER
} gl_functions;

/* Filled by gl_functions_load; read-only afterwards. */
extern gl_functions gl_fn;

#define glActiveTexture gl_fn.ActiveTexture
#define glAttachShader gl_fn.AttachShader
#define glBindBuffer gl_fn.BindBuffer
#define glBindFramebuffer gl_fn.BindFramebuffer
#define glBindRenderbuffer gl_fn.BindRenderbuffer
#define glBindTexture gl_fn.BindTexture
#define glBindVertexArray gl_fn.BindVertexArray
#define glBlendEquation gl_fn.BlendEquation
#define glBlendEquationSeparate gl_fn.BlendEquationSeparate
#define glBlendFunc gl_fn.BlendFunc
#define glBlitFramebuffer gl_fn.BlitFramebuffer
#define glBufferData gl_fn.BufferData
#define glBufferSubData gl_fn.BufferSubData
#define glCheckFramebufferStatus gl_fn.CheckFramebufferStatus
#define glClear gl_fn.Clear
#define glClearBufferfv gl_fn.ClearBufferfv
#define glClearColor gl_fn.ClearColor
#define glCompileShader gl_fn.CompileShader
#define glCreateProgram gl_fn.CreateProgram
#define glCreateShader gl_fn.CreateShader
#define glCullFace gl_fn.CullFace
#define glDeleteBuffers gl_fn.DeleteBuffers
#define glDeleteFramebuffers gl_fn.DeleteFramebuffers
#define glDeleteProgram gl_fn.DeleteProgram
#define glDeleteRenderbuffers gl_fn.DeleteRenderbuffers
#define glDeleteShader gl_fn.DeleteShader
#define glDeleteTextures gl_fn.DeleteTextures
#define glDeleteVertexArrays gl_fn.DeleteVertexArrays
#define glDepthMask gl_fn.DepthMask
#define glDisable gl_fn.Disable
#define glDrawArrays gl_fn.DrawArrays
#define glDrawBuffer gl_fn.DrawBuffer
#define glDrawBuffers gl_fn.DrawBuffers
#define glDrawElements gl_fn.DrawElements
#define glEnable gl_fn.Enable
#define glEnableVertexAttribArray gl_fn.EnableVertexAttribArray
#define glFinish gl_fn.Finish
#define glFramebufferRenderbuffer gl_fn.FramebufferRenderbuffer
#define glFramebufferTexture2D gl_fn.FramebufferTexture2D
#define glFrontFace gl_fn.FrontFace
#define glGenBuffers gl_fn.GenBuffers
#define glGenFramebuffers gl_fn.GenFramebuffers
#define glGenRenderbuffers gl_fn.GenRenderbuffers
#define glGenTextures gl_fn.GenTextures
#define glGenVertexArrays gl_fn.GenVertexArrays
#define glGetError gl_fn.GetError
#define glGetIntegerv gl_fn.GetIntegerv
#define glGetProgramInfoLog gl_fn.GetProgramInfoLog
#define glGetProgramiv gl_fn.GetProgramiv
#define glGetShaderInfoLog gl_fn.GetShaderInfoLog
#define glGetShaderiv gl_fn.GetShaderiv
#define glGetString gl_fn.GetString
#define glGetUniformLocation gl_fn.GetUniformLocation
#define glLinkProgram gl_fn.LinkProgram
#define glPixelStorei gl_fn.PixelStorei
#define glPolygonOffset gl_fn.PolygonOffset
#define glReadBuffer gl_fn.ReadBuffer
#define glReadPixels gl_fn.ReadPixels
#define glRenderbufferStorage gl_fn.RenderbufferStorage
#define glRenderbufferStorageMultisample gl_fn.RenderbufferStorageMultisample
#define glScissor gl_fn.Scissor
#define glShaderSource gl_fn.ShaderSource
#define glTexImage2D gl_fn.TexImage2D
#define glTexParameteri gl_fn.TexParameteri
#define glUniform1f gl_fn.Uniform1f
#define glUniform1i gl_fn.Uniform1i
#define glUniform2f gl_fn.Uniform2f
#define glUniform3f gl_fn.Uniform3f
#define glUniform3fv gl_fn.Uniform3fv
#define glUniform4f gl_fn.Uniform4f
#define glUniform4fv gl_fn.Uniform4fv
#define glUniformMatrix4fv gl_fn.UniformMatrix4fv
#define glUseProgram gl_fn.UseProgram
#define glVertexAttribPointer gl_fn.VertexAttribPointer
#define glViewport gl_fn.Viewport
#endif /* GL_API_LOADER_ONLY */

#endif
