// An offscreen OpenGL 4.5 core-profile context through OSMesa (Mesa's software
// rasteriser, llvmpipe): rendering without a display, a GPU or a window system.
//
// How GL functions are reached: Debian's libOSMesa exports every GL entry point
// (glGenFramebuffers, glCreateShader, glGenVertexArrays, ... all 4.5 core) as a
// dispatch stub that calls into whichever OSMesa context is current on the calling
// thread. So we declare the prototypes (GL_GLEXT_PROTOTYPES) and link -lOSMesa; no
// loader library is needed. getProcAddress() is there for code that wants pointers
// (e.g. an extension the headers lack). Do not link libGL into the same binary:
// the two libraries would compete for the gl* symbols.
//
// Include this header before any other GL header in a translation unit, so that
// the prototypes in glext.h are declared (glext.h has an include guard).
//
// Threads: one context per thread. A context is current on at most one thread at a
// time; each thread that renders makes its own context (or uses forThisThread()).
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <string>
#include <vector>

namespace art2part {

class OffscreenContext {
 public:
  // Creates a core-profile context of at least the given version. Throws
  // std::runtime_error if OSMesa cannot (too old a Mesa, or a driver such as
  // softpipe that stops below 4.5).
  explicit OffscreenContext(int major_version = 4, int minor_version = 5);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  // Binds this context to the calling thread, with its small default buffer as
  // the window-system framebuffer. Real rendering goes into FBOs the caller makes.
  void makeCurrent();
  // Unbinds whatever OSMesa context is current on the calling thread.
  static void releaseCurrent();

  // A lazily created context owned by the calling thread, destroyed when the
  // thread ends; made current before it is returned. Callers that render now and
  // then (pictures, visibility) can share it instead of paying the creation each time.
  static OffscreenContext& forThisThread();

  // Address of a GL function by name (nullptr if unknown). Needs no current context.
  using Proc = void (*)();
  static Proc getProcAddress(const char* name);

  // GL_RENDERER / GL_VERSION of this context (makes it current).
  std::string renderer();
  std::string version();

 private:
  OSMesaContext context_ = nullptr;
  // OSMesaMakeCurrent needs a colour buffer; rendering goes to FBOs, so a tiny one.
  static constexpr int kDefaultBufferSize = 16;
  std::vector<unsigned char> default_buffer_;
};

// One stage of a shader program: its type (GL_VERTEX_SHADER, GL_GEOMETRY_SHADER, ...) and GLSL source.
struct ShaderStage {
  GLenum type = GL_VERTEX_SHADER;  // the pipeline stage
  std::string source;              // GLSL text
};

// Shader helpers. They need a current context and throw std::runtime_error
// carrying the GLSL info log. `name` only labels the error message.
GLuint compileShader(GLenum type, const std::string& source, const std::string& name);
// A program of the given stages, compiled and linked.
GLuint linkProgram(const std::vector<ShaderStage>& stages, const std::string& name);
// A program of a vertex and a fragment shader.
GLuint linkProgram(const std::string& vertex_source, const std::string& fragment_source,
                   const std::string& name);

// Throws std::runtime_error naming `what` if glGetError reports an error.
void checkGlError(const char* what);

}  // namespace art2part
