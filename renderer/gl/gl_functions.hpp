// The GL 4.5 core entry points geoslice uses, loaded per context through the backend's
// getProcAddress (eglGetProcAddress or OSMesaGetProcAddress). geoslice never links libGL,
// libOpenGL or libOSMesa: libOSMesa and libOpenGL both export the whole gl* API, and a
// process may use EGL and OSMesa contexts side by side. <GL/glcorearb.h> is included for
// types and enums only (no prototypes).
//
// Members carry the GL name without the "gl" prefix (gl.DrawElements(...) is
// glDrawElements), so that GL documentation reads across unchanged.
// Threads: a GlFunctions table belongs to the GlContext that loaded it; call its entries
// only on the thread where that context is current (see renderer/gl/gl_context.hpp).
#pragma once

#include <string>
#include <vector>

#include <GL/glcorearb.h>

namespace geoslice {

// X(type of the pointer, name without "gl").
#define GEOSLICE_GL_FUNCTIONS(X)                                                         \
    /* state and queries */                                                              \
    X(PFNGLGETERRORPROC, GetError)                                                       \
    X(PFNGLGETSTRINGPROC, GetString)                                                     \
    X(PFNGLGETSTRINGIPROC, GetStringi)                                                   \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                 \
    X(PFNGLGETFLOATVPROC, GetFloatv)                                                     \
    X(PFNGLENABLEPROC, Enable)                                                           \
    X(PFNGLDISABLEPROC, Disable)                                                         \
    X(PFNGLENABLEIPROC, Enablei)                                                         \
    X(PFNGLDISABLEIPROC, Disablei)                                                       \
    X(PFNGLVIEWPORTPROC, Viewport)                                                       \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                                                     \
    X(PFNGLDEPTHMASKPROC, DepthMask)                                                     \
    X(PFNGLCLIPCONTROLPROC, ClipControl)                                                 \
    X(PFNGLCULLFACEPROC, CullFace)                                                       \
    X(PFNGLFRONTFACEPROC, FrontFace)                                                     \
    X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                                             \
    X(PFNGLSTENCILFUNCPROC, StencilFunc)                                                 \
    X(PFNGLSTENCILOPPROC, StencilOp)                                                     \
    X(PFNGLSTENCILMASKPROC, StencilMask)                                                 \
    X(PFNGLCOLORMASKIPROC, ColorMaski)                                                   \
    X(PFNGLLINEWIDTHPROC, LineWidth)                                                     \
    X(PFNGLFINISHPROC, Finish)                                                           \
    X(PFNGLFLUSHPROC, Flush)                                                             \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                 \
    X(PFNGLREADPIXELSPROC, ReadPixels)                                                   \
    X(PFNGLREADNPIXELSPROC, ReadnPixels)                                                 \
    X(PFNGLDEBUGMESSAGECALLBACKPROC, DebugMessageCallback)                               \
    /* shaders and programs */                                                           \
    X(PFNGLCREATESHADERPROC, CreateShader)                                               \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                                               \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                                             \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                 \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                       \
    X(PFNGLDELETESHADERPROC, DeleteShader)                                               \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                             \
    X(PFNGLATTACHSHADERPROC, AttachShader)                                               \
    X(PFNGLDETACHSHADERPROC, DetachShader)                                               \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                 \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                               \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                     \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                             \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                                                   \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                   \
    X(PFNGLPROGRAMUNIFORM1IPROC, ProgramUniform1i)                                       \
    X(PFNGLPROGRAMUNIFORM1UIPROC, ProgramUniform1ui)                                     \
    X(PFNGLPROGRAMUNIFORM1UIVPROC, ProgramUniform1uiv)                                   \
    X(PFNGLPROGRAMUNIFORM3IPROC, ProgramUniform3i)                                       \
    X(PFNGLPROGRAMUNIFORM1FPROC, ProgramUniform1f)                                       \
    X(PFNGLPROGRAMUNIFORM2FVPROC, ProgramUniform2fv)                                     \
    X(PFNGLPROGRAMUNIFORM3FVPROC, ProgramUniform3fv)                                     \
    X(PFNGLPROGRAMUNIFORM4FVPROC, ProgramUniform4fv)                                     \
    X(PFNGLPROGRAMUNIFORMMATRIX4FVPROC, ProgramUniformMatrix4fv)                         \
    /* buffers and vertex arrays (DSA) */                                                \
    X(PFNGLCREATEBUFFERSPROC, CreateBuffers)                                             \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                             \
    X(PFNGLNAMEDBUFFERSTORAGEPROC, NamedBufferStorage)                                   \
    X(PFNGLNAMEDBUFFERSUBDATAPROC, NamedBufferSubData)                                   \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                                                   \
    X(PFNGLMAPNAMEDBUFFERRANGEPROC, MapNamedBufferRange)                                 \
    X(PFNGLUNMAPNAMEDBUFFERPROC, UnmapNamedBuffer)                                       \
    X(PFNGLCREATEVERTEXARRAYSPROC, CreateVertexArrays)                                   \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                   \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                         \
    X(PFNGLVERTEXARRAYVERTEXBUFFERPROC, VertexArrayVertexBuffer)                         \
    X(PFNGLVERTEXARRAYELEMENTBUFFERPROC, VertexArrayElementBuffer)                       \
    X(PFNGLVERTEXARRAYATTRIBFORMATPROC, VertexArrayAttribFormat)                         \
    X(PFNGLVERTEXARRAYATTRIBIFORMATPROC, VertexArrayAttribIFormat)                       \
    X(PFNGLVERTEXARRAYATTRIBBINDINGPROC, VertexArrayAttribBinding)                       \
    X(PFNGLENABLEVERTEXARRAYATTRIBPROC, EnableVertexArrayAttrib)                         \
    /* drawing */                                                                        \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                                                   \
    X(PFNGLDRAWELEMENTSPROC, DrawElements)                                               \
    X(PFNGLDRAWELEMENTSBASEVERTEXPROC, DrawElementsBaseVertex)                           \
    X(PFNGLMULTIDRAWELEMENTSBASEVERTEXPROC, MultiDrawElementsBaseVertex)                 \
    /* framebuffers and renderbuffers (DSA) */                                           \
    X(PFNGLCREATEFRAMEBUFFERSPROC, CreateFramebuffers)                                   \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                   \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                         \
    X(PFNGLNAMEDFRAMEBUFFERRENDERBUFFERPROC, NamedFramebufferRenderbuffer)               \
    X(PFNGLNAMEDFRAMEBUFFERDRAWBUFFERSPROC, NamedFramebufferDrawBuffers)                 \
    X(PFNGLNAMEDFRAMEBUFFERREADBUFFERPROC, NamedFramebufferReadBuffer)                   \
    X(PFNGLCHECKNAMEDFRAMEBUFFERSTATUSPROC, CheckNamedFramebufferStatus)                 \
    X(PFNGLCLEARNAMEDFRAMEBUFFERFVPROC, ClearNamedFramebufferfv)                         \
    X(PFNGLCLEARNAMEDFRAMEBUFFERUIVPROC, ClearNamedFramebufferuiv)                       \
    X(PFNGLCLEARNAMEDFRAMEBUFFERFIPROC, ClearNamedFramebufferfi)                         \
    X(PFNGLBLITNAMEDFRAMEBUFFERPROC, BlitNamedFramebuffer)                               \
    X(PFNGLCREATERENDERBUFFERSPROC, CreateRenderbuffers)                                 \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                                 \
    X(PFNGLNAMEDRENDERBUFFERSTORAGEPROC, NamedRenderbufferStorage)                       \
    X(PFNGLNAMEDRENDERBUFFERSTORAGEMULTISAMPLEPROC, NamedRenderbufferStorageMultisample) \
    X(PFNGLNAMEDFRAMEBUFFERTEXTUREPROC, NamedFramebufferTexture)                         \
    X(PFNGLGETINTERNALFORMATIVPROC, GetInternalformativ)                                 \
    /* textures (DSA) */                                                                 \
    X(PFNGLCREATETEXTURESPROC, CreateTextures)                                           \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                           \
    X(PFNGLTEXTURESTORAGE2DPROC, TextureStorage2D)                                       \
    X(PFNGLTEXTURESTORAGE3DPROC, TextureStorage3D)                                       \
    X(PFNGLTEXTURESUBIMAGE2DPROC, TextureSubImage2D)                                     \
    X(PFNGLTEXTURESUBIMAGE3DPROC, TextureSubImage3D)                                     \
    X(PFNGLTEXTUREPARAMETERIPROC, TextureParameteri)                                     \
    X(PFNGLBINDTEXTUREUNITPROC, BindTextureUnit)                                         \
    /* timing and sync */                                                                \
    X(PFNGLCREATEQUERIESPROC, CreateQueries)                                             \
    X(PFNGLDELETEQUERIESPROC, DeleteQueries)                                             \
    X(PFNGLQUERYCOUNTERPROC, QueryCounter)                                               \
    X(PFNGLGETQUERYOBJECTUI64VPROC, GetQueryObjectui64v)                                 \
    X(PFNGLFENCESYNCPROC, FenceSync)                                                     \
    X(PFNGLCLIENTWAITSYNCPROC, ClientWaitSync)                                           \
    X(PFNGLDELETESYNCPROC, DeleteSync)

struct GlFunctions {
#define GEOSLICE_GL_MEMBER(type, name) type name = nullptr;
    GEOSLICE_GL_FUNCTIONS(GEOSLICE_GL_MEMBER)
#undef GEOSLICE_GL_MEMBER

    using ProcAddressFn = void* (*)(const char* name, void* user);
    // Fills every entry with getProc("glName", user). Returns the names that came back null
    // (empty = complete). Call with the context current on the calling thread: some
    // getProcAddress implementations need it.
    std::vector<std::string> load(ProcAddressFn getProc, void* user);
    static std::size_t count();
};

// Name of a GL error code ("GL_INVALID_OPERATION"), or "GL error 0x...." when unknown.
std::string glErrorName(GLenum error);

}  // namespace geoslice
