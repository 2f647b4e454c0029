// Shaded pictures of a mesh: core-profile GL into an FBO, read back, PNG out.
#include "art2part/render/offscreen_context.h"  // first: GL prototypes
#include "art2part/render/picture.h"

#include <Eigen/Geometry>  // cross()
#include <png.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace art2part {

namespace {

const std::array<unsigned char, 3> kDefaultColour = {160, 175, 200};  // grey-blue
const float kBackground[4] = {0.97f, 0.97f, 0.97f, 1.0f};
const double kMargin = 0.05;  // fraction of the picture left free around the part

// The vertex shader gets positions already in view space (mm, relative to the
// picture centre, computed in double on the CPU so large coordinates lose no
// precision) and only scales them into the orthographic clip box. The corner
// barycentrics come from gl_VertexID because the vertices are un-indexed.
const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 colour;
uniform vec3 scale;
out vec3 view_position;
flat out vec3 base_colour;
noperspective out vec3 barycentric;
void main() {
  view_position = position;
  base_colour = colour;
  barycentric = vec3(0.0);
  barycentric[gl_VertexID % 3] = 1.0;
  // The eye looks along -z: larger z is nearer, so it gets the smaller depth.
  gl_Position = vec4(position.xy * scale.xy, -position.z * scale.z, 1.0);
}
)";

// Flat shading without per-vertex normals: the screen-space derivatives of the
// view-space position span the triangle's plane, so their cross product is the
// face normal. Flipping it towards the eye lights both sides alike, which keeps
// open meshes and wrongly oriented triangles from rendering black.
const char* kFragmentShader = R"(#version 450 core
in vec3 view_position;
flat in vec3 base_colour;
noperspective in vec3 barycentric;
uniform bool draw_edges;
out vec4 colour;
void main() {
  vec3 n = cross(dFdx(view_position), dFdy(view_position));
  n = length(n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
  if (n.z < 0.0) n = -n;
  const vec3 key = normalize(vec3(-0.4, 0.6, 1.0));   // upper left, in front
  const vec3 fill = normalize(vec3(0.7, -0.4, 0.5));  // lower right, weaker
  float light = 0.3 + 0.6 * max(dot(n, key), 0.0) + 0.25 * max(dot(n, fill), 0.0);
  vec3 shaded = min(base_colour * light, vec3(1.0));
  if (draw_edges) {
    // About one pixel wide, anti-aliased, whatever the triangle's size.
    vec3 a = smoothstep(vec3(0.0), fwidth(barycentric), barycentric);
    shaded = mix(shaded * 0.3, shaded, min(min(a.x, a.y), a.z));
  }
  colour = vec4(shaded, 1.0);
}
)";

// Orthographic camera: an orthonormal frame plus the half extents of the box it shows.
struct View {
  Vec3 right, up, back;  // back points from the part towards the eye
  Vec3 origin;           // world point at the picture centre
  Vec3 half;             // half width, half height, half depth in mm
};

View fitView(const Mesh& mesh, const PictureOptions& options) {
  View view;
  view.back = options.view_direction.normalized();
  // +Z up reads naturally for a part on a machine table; fall back to +Y when
  // looking (almost) straight along Z.
  Vec3 world_up = std::abs(view.back.z()) > 0.999 ? Vec3::UnitY() : Vec3::UnitZ();
  view.right = world_up.cross(view.back).normalized();
  view.up = view.back.cross(view.right);

  // Fit every vertex, not the bounding box corners: a tighter frame.
  Box box;
  for (const Vec3& p : mesh.vertices) box.extend(Vec3(p.dot(view.right), p.dot(view.up), p.dot(view.back)));
  if (box.empty()) box.extend(Vec3::Zero());
  Vec3 c = box.center();
  view.origin = c.x() * view.right + c.y() * view.up + c.z() * view.back;

  // Keep the pixels square: widen whichever extent is short for the aspect ratio.
  double aspect = double(options.width) / options.height;
  Vec3 size = box.size().cwiseMax(Vec3::Constant(1e-6));
  double half_width = 0.5 * std::max(size.x(), size.y() * aspect) / (1.0 - 2.0 * kMargin);
  view.half = Vec3(half_width, half_width / aspect, 0.5 * size.z() * 1.01 + 1e-6);
  return view;
}

// Un-indexed triangle corners in view space, three floats each.
std::vector<float> viewPositions(const Mesh& mesh, const View& view) {
  const int vertex_count = static_cast<int>(mesh.vertices.size());
  std::vector<float> out;
  out.reserve(mesh.triangles.size() * 9);
  for (const Triangle& t : mesh.triangles) {
    for (int index : t) {
      if (index < 0 || index >= vertex_count) throw std::invalid_argument("renderPicture: triangle refers to a missing vertex");
      Vec3 d = mesh.vertices[index] - view.origin;
      out.push_back(static_cast<float>(d.dot(view.right)));
      out.push_back(static_cast<float>(d.dot(view.up)));
      out.push_back(static_cast<float>(d.dot(view.back)));
    }
  }
  return out;
}

// One RGBA8 colour per corner (4 bytes keeps attributes aligned), repeated per triangle.
std::vector<unsigned char> cornerColours(const PictureOptions& options) {
  std::vector<unsigned char> out;
  out.reserve(options.triangle_colours.size() * 12);
  for (const auto& c : options.triangle_colours)
    for (int corner = 0; corner < 3; ++corner) out.insert(out.end(), {c[0], c[1], c[2], 255});
  return out;
}

// Every GL object one picture needs, deleted on scope exit (the context stays current).
struct GlObjects {
  GLuint program = 0, vao = 0, buffers[2] = {0, 0};
  GLuint framebuffers[2] = {0, 0}, renderbuffers[3] = {0, 0, 0};
  ~GlObjects() {
    glDeleteProgram(program);
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(2, buffers);
    glDeleteFramebuffers(2, framebuffers);
    glDeleteRenderbuffers(3, renderbuffers);
  }
};

void uploadGeometry(GlObjects& gl, const Mesh& mesh, const View& view, const PictureOptions& options) {
  glGenVertexArrays(1, &gl.vao);
  glBindVertexArray(gl.vao);
  glGenBuffers(2, gl.buffers);

  std::vector<float> positions = viewPositions(mesh, view);
  glBindBuffer(GL_ARRAY_BUFFER, gl.buffers[0]);
  glBufferData(GL_ARRAY_BUFFER, positions.size() * sizeof(float), positions.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);

  if (options.triangle_colours.empty()) {
    // A constant attribute instead of an array: no per-vertex memory.
    glDisableVertexAttribArray(1);
    glVertexAttrib3f(1, kDefaultColour[0] / 255.0f, kDefaultColour[1] / 255.0f, kDefaultColour[2] / 255.0f);
    return;
  }
  std::vector<unsigned char> colours = cornerColours(options);
  glBindBuffer(GL_ARRAY_BUFFER, gl.buffers[1]);
  glBufferData(GL_ARRAY_BUFFER, colours.size(), colours.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(1, 3, GL_UNSIGNED_BYTE, GL_TRUE, 4, nullptr);
  glEnableVertexAttribArray(1);
}

// A framebuffer with an RGBA8 colour and (optionally) a depth renderbuffer.
GLuint makeFramebuffer(GlObjects& gl, int slot, int width, int height, int samples, bool depth) {
  GLuint& fbo = gl.framebuffers[slot];
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  GLuint colour_rb = 0, depth_rb = 0;
  glGenRenderbuffers(1, &colour_rb);
  gl.renderbuffers[slot == 0 ? 0 : 2] = colour_rb;
  glBindRenderbuffer(GL_RENDERBUFFER, colour_rb);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_rb);
  if (depth) {
    glGenRenderbuffers(1, &depth_rb);
    gl.renderbuffers[1] = depth_rb;
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
  }
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("renderPicture: offscreen framebuffer incomplete");
  return fbo;
}

void checkOptions(const Mesh& mesh, const PictureOptions& options) {
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  if (options.width < 1 || options.height < 1 || options.width > max_size || options.height > max_size)
    throw std::invalid_argument("renderPicture: picture size must be 1.." + std::to_string(max_size) + " pixels");
  if (!options.triangle_colours.empty() && options.triangle_colours.size() != mesh.triangles.size())
    throw std::invalid_argument("renderPicture: triangle_colours must be empty or one per triangle");
  if (!(options.view_direction.norm() > 0)) throw std::invalid_argument("renderPicture: zero view_direction");
}

// Reads the bound read framebuffer; GL's rows run bottom-up, PNG's top-down.
Image readImage(int width, int height) {
  std::vector<unsigned char> rgba(size_t(4) * width * height);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  Image image{width, height, std::vector<unsigned char>(size_t(3) * width * height)};
  for (int y = 0; y < height; ++y) {
    const unsigned char* src = &rgba[size_t(4) * width * (height - 1 - y)];
    unsigned char* dst = &image.rgb[size_t(3) * width * y];
    for (int x = 0; x < width; ++x, src += 4, dst += 3) std::copy(src, src + 3, dst);
  }
  return image;
}

}  // namespace

Image renderPicture(const Mesh& mesh, const PictureOptions& options) {
  return renderPicture(OffscreenContext::forThisThread(), mesh, options);
}

Image renderPicture(OffscreenContext& context, const Mesh& mesh, const PictureOptions& options) {
  context.makeCurrent();
  checkOptions(mesh, options);
  const int w = options.width, h = options.height;
  GLint max_samples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  const int samples = std::clamp(options.samples, 1, std::max(1, int(max_samples)));

  GlObjects gl;
  gl.program = linkProgram(kVertexShader, kFragmentShader, "picture");
  View view = fitView(mesh, options);
  uploadGeometry(gl, mesh, view, options);
  GLuint draw_fbo = makeFramebuffer(gl, 0, w, h, samples > 1 ? samples : 0, true);

  glViewport(0, 0, w, h);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);  // both sides drawn: open meshes have visible insides
  glClearBufferfv(GL_COLOR, 0, kBackground);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  glUseProgram(gl.program);
  glUniform3f(glGetUniformLocation(gl.program, "scale"), float(1.0 / view.half.x()),
              float(1.0 / view.half.y()), float(1.0 / view.half.z()));
  glUniform1i(glGetUniformLocation(gl.program, "draw_edges"), options.draw_edges ? 1 : 0);
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(3 * mesh.triangles.size()));

  GLuint read_fbo = draw_fbo;
  if (samples > 1) {  // resolve the multisampled picture into a plain one
    read_fbo = makeFramebuffer(gl, 1, w, h, 0, false);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, read_fbo);
    glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, read_fbo);
  Image image = readImage(w, h);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);
  glUseProgram(0);
  checkGlError("renderPicture");
  return image;
}

void writePng(const Image& image, const std::string& path) {
  if (image.width < 1 || image.height < 1 || image.rgb.size() != size_t(3) * image.width * image.height)
    throw std::runtime_error("writePng " + path + ": image size does not match its pixels");
  // libpng's simplified API: no setjmp/longjmp error handling to get wrong.
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  if (!png_image_write_to_file(&png, path.c_str(), 0, image.rgb.data(), 3 * image.width, nullptr)) {
    std::string message = png.message;
    png_image_free(&png);
    throw std::runtime_error("writePng " + path + ": " + message);
  }
}

}  // namespace art2part
