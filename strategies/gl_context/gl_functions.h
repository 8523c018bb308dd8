// The OpenGL entry points nurbsbench's GL strategies use, as a table filled per context from the
// platform's own GetProcAddress (OSMesaGetProcAddress or eglGetProcAddress).
//
// Why a table and not GL_GLEXT_PROTOTYPES + linking: libOSMesa and glvnd's libGL/libOpenGL both
// export the same gl* symbols, so a binary linking both would bind every gl* call to whichever
// library the dynamic linker saw first, whatever context is current. Resolving through the active
// platform's loader makes each call reach the driver that owns the context; nothing links libGL.
#pragma once

#include <GL/glcorearb.h>

namespace nurbs::gl {

// X(type, name): every function the GL strategies call. Add a line here to use a new one.
#define NURBSBENCH_GL_FUNCTIONS(X)                               \
  X(PFNGLGETSTRINGPROC, GetString)                               \
  X(PFNGLGETSTRINGIPROC, GetStringi)                             \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                           \
  X(PFNGLGETERRORPROC, GetError)                                 \
  X(PFNGLENABLEPROC, Enable)                                     \
  X(PFNGLBLENDFUNCPROC, BlendFunc)                               \
  X(PFNGLDISABLEPROC, Disable)                                   \
  X(PFNGLFINISHPROC, Finish)                                     \
  X(PFNGLFENCESYNCPROC, FenceSync)                               \
  X(PFNGLCLIENTWAITSYNCPROC, ClientWaitSync)                     \
  X(PFNGLDELETESYNCPROC, DeleteSync)                             \
  X(PFNGLVIEWPORTPROC, Viewport)                                 \
  X(PFNGLCLEARCOLORPROC, ClearColor)                             \
  X(PFNGLCLEARPROC, Clear)                                       \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                           \
  X(PFNGLREADBUFFERPROC, ReadBuffer)                             \
  X(PFNGLGENTEXTURESPROC, GenTextures)                           \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                     \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                           \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                       \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D)                             \
  X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                       \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                       \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                   \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)             \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)         \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)     \
  X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                           \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                   \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)             \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                   \
  X(PFNGLCREATESHADERPROC, CreateShader)                         \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                         \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                       \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                           \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                 \
  X(PFNGLDELETESHADERPROC, DeleteShader)                         \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                       \
  X(PFNGLATTACHSHADERPROC, AttachShader)                         \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                           \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                         \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)               \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                       \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                             \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)             \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                               \
  X(PFNGLGENQUERIESPROC, GenQueries)                             \
  X(PFNGLDELETEQUERIESPROC, DeleteQueries)                       \
  X(PFNGLBEGINQUERYPROC, BeginQuery)                             \
  X(PFNGLENDQUERYPROC, EndQuery)                                 \
  X(PFNGLGETQUERYOBJECTUI64VPROC, GetQueryObjectui64v)           \
  X(PFNGLDEBUGMESSAGECALLBACKPROC, DebugMessageCallback)         \
  X(PFNGLDEBUGMESSAGECONTROLPROC, DebugMessageControl)           \
  X(PFNGLUNIFORM2IPROC, Uniform2i)                               \
  X(PFNGLUNIFORM4IPROC, Uniform4i)                               \
  X(PFNGLUNIFORM1FVPROC, Uniform1fv)                             \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                 \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                             \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                       \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                             \
  X(PFNGLBUFFERDATAPROC, BufferData)                             \
  X(PFNGLGETBUFFERPARAMETERIVPROC, GetBufferParameteriv)         \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)           \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)   \
  X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, DisableVertexAttribArray) \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                 \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)           \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                 \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)           \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)

// The draws, the framebuffer bindings and the reads of device memory are not in Functions: they
// are reachable only through Context::draw_arrays / draw_arrays_instanced / draw_elements /
// bind_framebuffer / read_pixels / copy_pixels_to_buffer / read_buffer / map_buffer, which count
// them (a buffer mapped for reading is a host read-back), so the pass counts a strategy records
// are the draws it issued, and a path said to read nothing back to the host is checked by a count
// no read can bypass.
#define NURBSBENCH_GL_COUNTED_FUNCTIONS(X)             \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)         \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                   \
  X(PFNGLDRAWARRAYSINSTANCEDPROC, DrawArraysInstanced) \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)               \
  X(PFNGLREADPIXELSPROC, ReadPixels)                   \
  X(PFNGLGETBUFFERSUBDATAPROC, GetBufferSubData)       \
  X(PFNGLMAPBUFFERRANGEPROC, MapBufferRange)           \
  X(PFNGLUNMAPBUFFERPROC, UnmapBuffer)

#define NURBSBENCH_GL_DECLARE(type, name) type name = nullptr;
struct Functions {
  NURBSBENCH_GL_FUNCTIONS(NURBSBENCH_GL_DECLARE)
};
struct CountedFunctions {
  NURBSBENCH_GL_COUNTED_FUNCTIONS(NURBSBENCH_GL_DECLARE)
};
#undef NURBSBENCH_GL_DECLARE

}  // namespace nurbs::gl
