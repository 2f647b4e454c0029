// OSMesa context creation and the small GL utilities shared by the renderers.
#include "art2part/render/offscreen_context.h"

#include <memory>
#include <mutex>
#include <stdexcept>

namespace art2part {

namespace {

std::string glString(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : std::string("(unknown)");
}

const char* glErrorName(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "GL error";
  }
}

// The info log of a shader or program: get_iv and get_log are glGetShaderiv and glGetShaderInfoLog, or the program's.
template <class GetIv, class GetLog>
std::string infoLog(GLuint object, GetIv get_iv, GetLog get_log) {
  GLint length = 0;
  get_iv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(length > 0 ? length : 1), '\0');
  get_log(object, static_cast<GLsizei>(log.size()), nullptr, &log[0]);
  return log.c_str();  // up to the terminating zero
}

std::mutex& contextLifetimeMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

OffscreenContext::OffscreenContext(int major_version, int minor_version)
    : default_buffer_(4 * kDefaultBufferSize * kDefaultBufferSize, 0) {
  // No depth/stencil in the default buffer: renderers attach their own to FBOs.
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            0,
                            OSMESA_STENCIL_BITS,
                            0,
                            OSMESA_ACCUM_BITS,
                            0,
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            major_version,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            minor_version,
                            0};
  {
    // Mesa's context creation and destruction touch process-wide state (the GL dispatch, llvmpipe's screen):
    // worker threads creating or dropping their contexts at once crashed now and then. One at a time.
    std::lock_guard<std::mutex> lock(contextLifetimeMutex());
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
  }
  if (!context_) {
    throw std::runtime_error(
        "OSMesa could not create an OpenGL " + std::to_string(major_version) + "." +
        std::to_string(minor_version) +
        " core-profile context (needs Mesa's llvmpipe driver; check that GALLIUM_DRIVER "
        "is unset or 'llvmpipe' and that libOSMesa is Mesa 20 or newer)");
  }
  makeCurrent();
}

OffscreenContext::~OffscreenContext() {
  // Unbind first if this context is current here, so the thread is not left
  // pointing at a destroyed context.
  if (OSMesaGetCurrentContext() == context_) releaseCurrent();
  std::lock_guard<std::mutex> lock(contextLifetimeMutex());
  OSMesaDestroyContext(context_);
}

void OffscreenContext::makeCurrent() {
  if (OSMesaGetCurrentContext() == context_) return;  // cheap repeated calls
  if (!OSMesaMakeCurrent(context_, default_buffer_.data(), GL_UNSIGNED_BYTE,
                         kDefaultBufferSize, kDefaultBufferSize)) {
    throw std::runtime_error("OSMesaMakeCurrent failed");
  }
}

void OffscreenContext::releaseCurrent() {
  OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
}

OffscreenContext& OffscreenContext::forThisThread() {
  // A unique_ptr, not a plain thread_local object, so that a failed creation
  // throws on every call instead of leaving a half-built object behind.
  thread_local std::unique_ptr<OffscreenContext> context;
  if (!context) context = std::make_unique<OffscreenContext>();
  context->makeCurrent();
  return *context;
}

OffscreenContext::Proc OffscreenContext::getProcAddress(const char* name) {
  return reinterpret_cast<Proc>(OSMesaGetProcAddress(name));
}

std::string OffscreenContext::renderer() {
  makeCurrent();
  return glString(GL_RENDERER);
}

std::string OffscreenContext::version() {
  makeCurrent();
  return glString(GL_VERSION);
}

GLuint compileShader(GLenum type, const std::string& source, const std::string& name) {
  GLuint shader = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return shader;
  const std::string log = infoLog(shader, glGetShaderiv, glGetShaderInfoLog);
  glDeleteShader(shader);
  const char* kind = type == GL_VERTEX_SHADER     ? "vertex"
                     : type == GL_GEOMETRY_SHADER ? "geometry"
                     : type == GL_FRAGMENT_SHADER ? "fragment"
                                                  : "";
  throw std::runtime_error("compiling " + std::string(kind) + " shader of " + name + ": " + log);
}

GLuint linkProgram(const std::vector<ShaderStage>& stages, const std::string& name) {
  std::vector<GLuint> shaders;
  try {
    for (const ShaderStage& stage : stages) shaders.push_back(compileShader(stage.type, stage.source, name));
  } catch (...) {
    for (GLuint shader : shaders) glDeleteShader(shader);
    throw;
  }
  GLuint program = glCreateProgram();
  for (GLuint shader : shaders) glAttachShader(program, shader);
  glLinkProgram(program);
  // The program keeps the compiled code; the shader objects can go now.
  for (GLuint shader : shaders) glDeleteShader(shader);

  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok) return program;
  const std::string log = infoLog(program, glGetProgramiv, glGetProgramInfoLog);
  glDeleteProgram(program);
  throw std::runtime_error("linking shader program " + name + ": " + log);
}

GLuint linkProgram(const std::string& vertex_source, const std::string& fragment_source,
                   const std::string& name) {
  return linkProgram({{GL_VERTEX_SHADER, vertex_source}, {GL_FRAGMENT_SHADER, fragment_source}}, name);
}

void checkGlError(const char* what) {
  GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  // Drain the queue so the next check does not report this error again.
  while (glGetError() != GL_NO_ERROR) {
  }
  throw std::runtime_error(std::string("OpenGL error in ") + what + ": " + glErrorName(error));
}

}  // namespace art2part
