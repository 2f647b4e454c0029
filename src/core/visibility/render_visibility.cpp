// Visibility by rendering triangle ids (thesis 3.2.1): one orthographic view per direction into an R32UI target
// holding gl_PrimitiveID + 1, read back; every id seen marks its triangle visible along that direction.
// Worker threads each own an OSMesa context with the mesh uploaded once and claim directions one at a time.
// Cost is per triangle per view (llvmpipe's triangle setup) plus pixels: about 50-130 ms of CPU per view for 120k
// triangles at 512-2048 pixels, half that when back faces can be culled.
//
// A triangle that covers no pixel centre never wins a pixel: thin CAD fan triangles, triangles smaller than a pixel,
// a strip of a triangle peeking out from under an occluder. By default rays settle those (render_fallback.h): the
// triangles thinner than 1.5 pixels that no pixel showed, and the hidden neighbours of shown triangles from just
// inside the shared edge. The older answer, off by default since the exact oracle found it wrong more often than
// right on organic meshes: with outlines on, one more pass draws every
// front-facing triangle's outline, drawn just inside it, against the finished depth buffer, every fragment that
// passes marking its triangle in a storage buffer. Unlike ids in pixels, marks never overwrite each
// other, so a sliver between two neighbours that share all its pixels is still seen.
#include "art2part/render/offscreen_context.h"  // first: GL prototypes
#include "art2part/common/parallel.h"
#include "art2part/visibility/visibility.h"
#include "render_fallback.h"
#include "render_scene.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace art2part {

namespace {

using idrender::Scene;
using idrender::View;

// Positions arrive relative to the bounding-sphere centre; `view` rotates them into the eye frame (right, up,
// back) and divides by the radius, so the sphere fills the clip cube exactly in x, y and depth: the depth range
// is as tight as the part allows without clipping any orientation.
const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
uniform mat3 view;
void main() {
  vec3 p = view * position;
  gl_Position = vec4(p.xy, -p.z, 1.0);  // larger "back" is nearer the eye: smaller depth
}
)";

// Back faces write 0 yet still write depth, so they hide what lies behind them (open meshes, thin walls). The
// mesh is counter-clockwise from outside and the frame right-handed, so GL's default CCW front face is "n.d > 0".
const char* kFragmentShader = R"(#version 450 core
layout(location = 0) out uint id;
void main() { id = gl_FrontFacing ? uint(gl_PrimitiveID + 1) : 0u; }
)";

// The outline pass draws each front-facing triangle's outline moved inwards by kInset pixels (a triangle thinner
// than that shrinks by half about its incentre instead). Inwards, because an outline tested at the pixel centre next
// to it would otherwise see past an occluder whose silhouette runs along the edge (a slot's floor under a ceiling
// with the same outline). Its depth is pulled towards the eye by the triangle's depth change over kInset pixels, so
// it beats its own fill at the nearest pixel centre and no nearer geometry.
const char* kOutlineGeometryShader = R"(#version 450 core
layout(triangles) in;
layout(line_strip, max_vertices = 4) out;
uniform float pixel;  // the width of a pixel in clip units
uniform float inset;  // in pixels
flat out int triangle;
void main() {
  vec3 p[3] = vec3[3](gl_in[0].gl_Position.xyz, gl_in[1].gl_Position.xyz, gl_in[2].gl_Position.xyz);
  vec2 e1 = p[1].xy - p[0].xy, e2 = p[2].xy - p[0].xy;
  float area2 = e1.x * e2.y - e1.y * e2.x;  // twice the signed area: counter-clockwise is front-facing
  if (!(area2 > 0.0)) return;
  float a = length(p[1].xy - p[2].xy), b = length(p[2].xy - p[0].xy), c = length(e1);
  vec3 centre = (a * p[0] + b * p[1] + c * p[2]) / (a + b + c);
  float radius = area2 / (a + b + c);  // inradius
  float keep = radius > inset * pixel ? 1.0 - inset * pixel / radius : 0.5;
  float dzx = (e2.y * (p[1].z - p[0].z) - e1.y * (p[2].z - p[0].z)) / area2;
  float dzy = (e1.x * (p[2].z - p[0].z) - e2.x * (p[1].z - p[0].z)) / area2;
  float pull = min((abs(dzx) + abs(dzy)) * inset * pixel, 8.0 * pixel) + 1e-6;
  for (int k = 0; k < 4; ++k) {
    vec3 q = centre + keep * (p[k % 3] - centre);
    gl_Position = vec4(q.xy, q.z - pull, 1.0);
    triangle = gl_PrimitiveIDIn;
    EmitVertex();
  }
  EndPrimitive();
}
)";

// Early depth tests, so that a fragment hidden by the depth buffer leaves no mark (a shader with side effects
// would otherwise run before the test).
const char* kMarkShader = R"(#version 450 core
layout(early_fragment_tests) in;
layout(std430, binding = 0) writeonly buffer Marks { uint marks[]; };
uniform uint stamp;
flat in int triangle;
void main() { marks[triangle] = stamp; }
)";

GLuint linkOutlineProgram() {
  return linkProgram({{GL_VERTEX_SHADER, kVertexShader},
                      {GL_GEOMETRY_SHADER, kOutlineGeometryShader},
                      {GL_FRAGMENT_SHADER, kMarkShader}},
                     "visibility outlines");
}

// Pixels the outline keeps inside its triangle: more than half, so the pixel centre a fragment is tested at (within
// half a pixel of the line) lies inside the triangle.
constexpr float kInset = 0.75f;


// The GL objects of one worker's context: the mesh uploaded once, one framebuffer reused for every view.
class ViewRenderer {
 public:
  explicit ViewRenderer(const Scene& scene) : scene_(scene), n_(scene.resolution) {
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    if (n_ < 1 || n_ > max_size)
      throw std::invalid_argument("renderVisibility: resolution must be 1.." + std::to_string(max_size));
    program_ = linkProgram(kVertexShader, kFragmentShader, "visibility");
    view_location_ = glGetUniformLocation(program_, "view");
    if (scene_.outlines) makeMarkProgram();
    upload();
    makeFramebuffer();
    checkGlError("renderVisibility setup");
  }
  ~ViewRenderer() {
    glDeleteProgram(program_);
    glDeleteProgram(mark_program_);
    glDeleteBuffers(1, &marks_buffer_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteBuffers(2, buffers_);
    glDeleteFramebuffers(1, &fbo_);
    glDeleteRenderbuffers(2, renderbuffers_);
  }
  ViewRenderer(const ViewRenderer&) = delete;
  ViewRenderer& operator=(const ViewRenderer&) = delete;

  // Renders direction d; `ids` gets the view's rectangle, row by row: gl_PrimitiveID + 1, 0 = nothing or a back face.
  void render(const Vec3& d, std::vector<GLuint>& ids) {
    const View view = idrender::makeView(d, scene_);
    const GLuint zero[4] = {0, 0, 0, 0};
    glClearBufferuiv(GL_COLOR, 0, zero);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUniformMatrix3fv(view_location_, 1, GL_TRUE, view.rows);
    glDrawElements(GL_TRIANGLES, GLsizei(scene_.indices.size()), GL_UNSIGNED_INT, nullptr);
    ids.resize(std::size_t(view.width) * view.height);  // within the capacity reserved once: no reallocation
    glReadPixels(view.x, view.y, view.width, view.height, GL_RED_INTEGER, GL_UNSIGNED_INT, ids.data());
  }

  // After render(): marks every front-facing triangle with an edge or corner that shows, by setting its entry of
  // `marks` (one per triangle, kept between views) to `stamp`.
  void markOutlines(const Vec3& d, GLuint stamp, std::vector<GLuint>& marks) {
    const View view = idrender::makeView(d, scene_);
    glUseProgram(mark_program_);
    glUniformMatrix3fv(mark_view_location_, 1, GL_TRUE, view.rows);
    glUniform1ui(stamp_location_, stamp);
    setOutlineState(true);
    glDrawElements(GL_TRIANGLES, GLsizei(scene_.indices.size()), GL_UNSIGNED_INT, nullptr);
    setOutlineState(false);
    glUseProgram(program_);
    marks.resize(scene_.normals.size());
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, marks.size() * sizeof(GLuint), marks.data());
  }

 private:
  void makeMarkProgram() {
    mark_program_ = linkOutlineProgram();
    mark_view_location_ = glGetUniformLocation(mark_program_, "view");
    stamp_location_ = glGetUniformLocation(mark_program_, "stamp");
    glUseProgram(mark_program_);
    glUniform1f(glGetUniformLocation(mark_program_, "pixel"), 2.0f / n_);
    glUniform1f(glGetUniformLocation(mark_program_, "inset"), kInset);
    const std::vector<GLuint> zeros(std::max<std::size_t>(scene_.normals.size(), 1), 0);  // no stamp is 0
    glGenBuffers(1, &marks_buffer_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, marks_buffer_);
    glBufferData(GL_SHADER_STORAGE_BUFFER, zeros.size() * sizeof(GLuint), zeros.data(), GL_DYNAMIC_READ);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, marks_buffer_);
  }

  // The outline pass tests against the fill's depth without changing it or the ids; off restores the fill pass's
  // state (see makeFramebuffer()).
  void setOutlineState(bool on) {
    glDepthMask(on ? GL_FALSE : GL_TRUE);
    glDepthFunc(on ? GL_LEQUAL : GL_LESS);
    glColorMask(!on, !on, !on, !on);
  }

  void upload() {
    glGenVertexArrays(1, &vao_);
    glBindVertexArray(vao_);
    glGenBuffers(2, buffers_);
    glBindBuffer(GL_ARRAY_BUFFER, buffers_[0]);
    glBufferData(GL_ARRAY_BUFFER, scene_.positions.size() * sizeof(float), scene_.positions.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers_[1]);  // part of the VAO's state
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, scene_.indices.size() * sizeof(GLuint), scene_.indices.data(), GL_STATIC_DRAW);
  }

  void makeFramebuffer() {
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glGenRenderbuffers(2, renderbuffers_);
    glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[0]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_R32UI, n_, n_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, renderbuffers_[0]);
    glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[1]);
    // Float depth: the sphere's depth range maps onto [0, 1] with no 24-bit quantisation of near-coplanar faces.
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, n_, n_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, renderbuffers_[1]);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("renderVisibility: offscreen framebuffer incomplete");
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glViewport(0, 0, n_, n_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    if (scene_.cull) {
      glEnable(GL_CULL_FACE);  // GL's default: back faces, with counter-clockwise front faces
    } else {
      glDisable(GL_CULL_FACE);  // every triangle occludes, back faces included
    }
    glClearDepth(1.0);
    glUseProgram(program_);
  }

  const Scene& scene_;
  const int n_;
  GLuint program_ = 0, vao_ = 0, buffers_[2] = {0, 0}, fbo_ = 0, renderbuffers_[2] = {0, 0};
  GLint view_location_ = -1;
  GLuint mark_program_ = 0, marks_buffer_ = 0;
  GLint mark_view_location_ = -1, stamp_location_ = -1;
};

// State the workers share. Results are merged under `mutex`; the calling thread alone calls the user's progress
// function (runTicking).
struct Shared {
  Shared(const Scene& s, const idrender::RayFallback* f, const std::vector<Vec3>& d, BitMatrix& b)
      : scene(s), fallback(f), directions(d), bits(b) {}
  const Scene& scene;
  const idrender::RayFallback* fallback;  // null: pixels and outlines alone
  const std::vector<Vec3>& directions;
  BitMatrix& bits;
  std::atomic<int> next{0};  // next direction to claim
  std::atomic<int> done{0};  // directions finished
  std::mutex mutex;          // guards bits
};

// Triangles seen in one view, each once. `stamp` remembers the last view that listed a triangle, so it never needs
// clearing. The n.d > 0 test in double makes the definition exact where float facing and it disagree (edge-on).
void collectVisible(const std::vector<GLuint>& pixels, const Scene& scene, const Vec3& d, int view,
                    std::vector<int>& stamp, std::vector<int>& visible) {
  visible.clear();
  GLuint last = 0;
  for (GLuint id : pixels) {
    if (id == 0 || id == last) continue;  // neighbouring pixels mostly show the same triangle
    last = id;
    const int t = static_cast<int>(id - 1);
    if (stamp[t] == view) continue;
    stamp[t] = view;
    if (scene.normals[t].dot(d) > 0) visible.push_back(t);
  }
}

// Adds the triangles the outline passes marked with `stamp` and no pixel showed.
void collectMarked(const std::vector<GLuint>& marks, GLuint stamp, const Scene& scene, const Vec3& d, int view,
                   std::vector<int>& seen, std::vector<int>& visible) {
  for (std::size_t t = 0; t < marks.size(); ++t) {
    if (marks[t] != stamp || seen[t] == view) continue;
    seen[t] = view;
    if (scene.normals[t].dot(d) > 0) visible.push_back(static_cast<int>(t));
  }
}

void renderDirections(Shared& shared, const std::atomic<bool>& stop) {
  OffscreenContext context;  // one per thread: OSMesa contexts are current on one thread at a time
  ViewRenderer renderer(shared.scene);
  std::unique_ptr<idrender::RayFallback::Tracer> rays;
  if (shared.fallback) rays = std::make_unique<idrender::RayFallback::Tracer>(*shared.fallback);
  std::vector<int> stamp(shared.scene.normals.size(), -1), visible;
  std::vector<GLuint> ids, marks;
  ids.reserve(std::size_t(shared.scene.resolution) * shared.scene.resolution);
  const int count = static_cast<int>(shared.directions.size());
  for (int d = shared.next++; d < count && !stop.load(); d = shared.next++) {
    const Vec3 direction = shared.directions[d].normalized();
    renderer.render(direction, ids);
    collectVisible(ids, shared.scene, direction, d, stamp, visible);
    if (shared.scene.outlines) {
      renderer.markOutlines(direction, GLuint(d + 1), marks);
      collectMarked(marks, GLuint(d + 1), shared.scene, direction, d, stamp, visible);
    }
    if (rays) rays->complete(direction, visible);
    std::lock_guard<std::mutex> lock(shared.mutex);  // other threads' bits share the same 64-bit words
    for (int t : visible) shared.bits.set(t, d);
    ++shared.done;
  }
  checkGlError("renderVisibility");
}

constexpr double kReportSeconds = 0.1;

int threadCount(const RenderVisibilityOptions& options, std::size_t directions) {
  int threads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp<int>(threads, 1, static_cast<int>(std::max<std::size_t>(directions, 1)));
}

}  // namespace

VisibilityMap renderVisibility(const Mesh& mesh, const std::vector<Vec3>& directions,
                               const RenderVisibilityOptions& options, const Progress& progress) {
  for (const Vec3& d : directions)
    if (!(d.norm() > 0) || !d.allFinite()) throw std::invalid_argument("renderVisibility: zero or invalid direction");
  VisibilityMap map{BitMatrix(mesh.triangleCount(), static_cast<int>(directions.size()))};
  if (mesh.triangles.empty() || directions.empty()) return map;
  if (progress && !progress(0.0)) throw std::runtime_error("cancelled");

  const Scene scene = idrender::prepareScene(mesh, options);
  std::unique_ptr<idrender::RayFallback> fallback;
  const double pixel = 2 * scene.radius / scene.resolution;
  if (options.ray_fallback) fallback = std::make_unique<idrender::RayFallback>(mesh, pixel);
  Shared shared(scene, fallback.get(), directions, map.bits);
  const double total = static_cast<double>(directions.size());
  const bool stopped = runTicking(
      threadCount(options, directions.size()),
      [&shared](int, const std::atomic<bool>& stop) { renderDirections(shared, stop); }, kReportSeconds,
      [&] { return !progress || progress(shared.done.load() / total); });
  if (stopped) throw std::runtime_error("cancelled");
  if (progress && !progress(1.0)) throw std::runtime_error("cancelled");
  return map;
}

}  // namespace art2part
