// Visibility by rendering triangle ids (thesis 3.2.1): one orthographic view per direction into an R32UI target
// holding gl_PrimitiveID + 1, read back; every id seen marks its triangle visible along that direction.
// Worker threads each own an OSMesa context with the mesh uploaded once and claim directions one at a time.
// Cost is per triangle per view (llvmpipe's triangle setup) plus pixels: about 50-130 ms of CPU per view for 120k
// triangles at 512-2048 pixels, half that when back faces can be culled. A triangle that covers no pixel centre
// in a view is missed there, so a coarse resolution loses visibility of small triangles.
#include "art2part/render/offscreen_context.h"  // first: GL prototypes
#include "art2part/visibility/visibility.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace art2part {

namespace {

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

// Everything the views share, computed once on the CPU and read by every worker.
struct Scene {
  std::vector<float> positions;  // xyz per vertex, relative to `centre`
  std::vector<GLuint> indices;   // three per triangle, in triangle order: gl_PrimitiveID == triangle index
  std::vector<Vec3> normals;     // unit, for the exact n.d > 0 test in double
  std::vector<Vec3> corners;     // of the bounding box, relative to `centre`: where the part can appear in a view
  double radius = 1;             // bounding sphere about the box centre, slightly enlarged
  int resolution = 64;
  bool cull = false;             // back faces can be skipped: see backFacesNeverShow()
};

double medianArea(const Mesh& mesh) {
  std::vector<double> areas(mesh.triangles.size());
  for (int t = 0; t < mesh.triangleCount(); ++t) areas[t] = triangleArea(mesh, t);
  if (areas.empty()) return 0;
  auto middle = areas.begin() + areas.size() / 2;
  std::nth_element(areas.begin(), middle, areas.end());
  return *middle;
}

// The thesis sizes views so that a typical triangle covers about 50 pixels (3.2.6). A view's side spans the
// bounding-sphere diameter 2R at N pixels, so a pixel is (2R/N)^2 and the median triangle, seen square-on (its
// true area A, its best case), covers A N^2 / 4R^2 pixels: N = 2R sqrt(ppt / A), clamped to [64, max_resolution].
// Triangles seen obliquely cover less: ones smaller than a pixel may fall between pixel centres and be missed.
int chooseResolution(const Mesh& mesh, double radius, const RenderVisibilityOptions& options) {
  if (options.resolution > 0) return options.resolution;
  const int max_resolution = std::max(64, options.max_resolution);
  const double area = medianArea(mesh);
  if (!(area > 0)) return max_resolution;
  const double n = std::ceil(2 * radius * std::sqrt(std::max(options.pixels_per_triangle, 0.0) / area));
  return static_cast<int>(std::clamp(n, 64.0, double(max_resolution)));
}

// Culling back faces gives the same pixels as drawing them when the surface is closed and oriented outwards: a
// line of sight from outside first meets the part where it enters it, on a front face, so a back face is never
// the nearest surface. It holds when every directed edge (a, b) is matched by exactly one (b, a) and every
// edge-connected shell encloses a positive volume. Anything else (an open mesh, an inside-out shell, a void)
// draws back faces too. Culling skips rasterising about half the triangles: a third less time per view.
bool backFacesNeverShow(const Mesh& mesh) {
  const int count = mesh.triangleCount();
  std::vector<std::pair<std::uint64_t, int>> edges;  // (a << 32 | b, triangle), sorted
  edges.reserve(3 * std::size_t(count));
  auto key = [](int a, int b) { return std::uint64_t(std::uint32_t(a)) << 32 | std::uint32_t(b); };
  for (int t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) edges.emplace_back(key(mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]), t);
  std::sort(edges.begin(), edges.end());
  std::vector<int> shell(count);  // union-find over triangles sharing an edge
  for (int t = 0; t < count; ++t) shell[t] = t;
  auto find = [&](int t) {
    while (shell[t] != t) t = shell[t] = shell[shell[t]];
    return t;
  };
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const std::uint64_t e = edges[i].first, reverse = e << 32 | e >> 32;
    if (i > 0 && edges[i - 1].first == e) return false;  // an edge run twice the same way
    auto twin = std::lower_bound(edges.begin(), edges.end(), std::make_pair(reverse, -1));
    if (twin == edges.end() || twin->first != reverse) return false;  // a boundary edge
    shell[find(edges[i].second)] = find(twin->second);
  }
  std::vector<double> volume(count, 0.0);  // six times each shell's signed volume, about the first vertex
  const Vec3 origin = mesh.vertices[mesh.triangles[0][0]];
  for (int t = 0; t < count; ++t) {
    const Vec3 a = mesh.corner(t, 0) - origin, b = mesh.corner(t, 1) - origin, c = mesh.corner(t, 2) - origin;
    volume[find(t)] += a.dot(b.cross(c));
  }
  for (int t = 0; t < count; ++t)
    if (find(t) == t && !(volume[t] > 0)) return false;
  return true;
}

Scene prepareScene(const Mesh& mesh, const RenderVisibilityOptions& options) {
  Scene scene;
  const Box box = boundingBox(mesh);
  const Vec3 centre = box.center();
  for (int i = 0; i < 8; ++i)
    scene.corners.emplace_back(Vec3(i & 1 ? box.max.x() : box.min.x(), i & 2 ? box.max.y() : box.min.y(),
                                    i & 4 ? box.max.z() : box.min.z()) - centre);
  double radius = 0;
  for (const Triangle& t : mesh.triangles)
    for (int v : t) {
      if (v < 0 || v >= static_cast<int>(mesh.vertices.size()))
        throw std::invalid_argument("renderVisibility: triangle refers to a missing vertex");
      radius = std::max(radius, (mesh.vertices[v] - centre).norm());
    }
  // A small margin keeps corners on the sphere off the clip planes, where float rounding could cut them.
  scene.radius = std::max(radius, 1e-9) * 1.001;
  scene.positions.reserve(3 * mesh.vertices.size());
  for (const Vec3& v : mesh.vertices)
    for (int k = 0; k < 3; ++k) scene.positions.push_back(static_cast<float>(v[k] - centre[k]));
  scene.indices.reserve(3 * mesh.triangles.size());
  scene.normals.reserve(mesh.triangles.size());
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    for (int v : mesh.triangles[t]) scene.indices.push_back(static_cast<GLuint>(v));
    scene.normals.push_back(triangleNormal(mesh, t));
  }
  scene.resolution = chooseResolution(mesh, scene.radius, options);
  scene.cull = backFacesNeverShow(mesh);
  return scene;
}

// One view: the matrix for the vertex shader and the pixel rectangle the part's box can cover.
struct View {
  float rows[9];  // right, up, back divided by the radius; back = d (towards the eye), right x up = back
  int x = 0, y = 0, width = 0, height = 0;
};

View makeView(const Vec3& d, const Scene& scene) {
  const Vec3 back = d.normalized();
  Eigen::Index least = 0;  // the axis least aligned with d makes the best-conditioned cross product
  back.cwiseAbs().minCoeff(&least);
  const Vec3 right = Vec3::Unit(least).cross(back).normalized();
  const Vec3 up = back.cross(right);
  View view;
  const Vec3 axes[3] = {right, up, back};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) view.rows[3 * r + c] = static_cast<float>(axes[r][c] / scene.radius);
  // Reading back only the box's shadow saves read-back and scanning, most for long thin parts.
  double lo[2] = {1, 1}, hi[2] = {-1, -1};
  for (const Vec3& corner : scene.corners)
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], corner.dot(axes[k]) / scene.radius);
      hi[k] = std::max(hi[k], corner.dot(axes[k]) / scene.radius);
    }
  const int n = scene.resolution;
  auto pixel = [n](double ndc) { return std::clamp(static_cast<int>(std::floor((ndc + 1) / 2 * n)), 0, n); };
  view.x = std::max(pixel(lo[0]) - 1, 0);  // a pixel of slack either side for rounding
  view.y = std::max(pixel(lo[1]) - 1, 0);
  view.width = std::min(pixel(hi[0]) + 2, n) - view.x;
  view.height = std::min(pixel(hi[1]) + 2, n) - view.y;
  return view;
}

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
    upload();
    makeFramebuffer();
    checkGlError("renderVisibility setup");
  }
  ~ViewRenderer() {
    glDeleteProgram(program_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteBuffers(2, buffers_);
    glDeleteFramebuffers(1, &fbo_);
    glDeleteRenderbuffers(2, renderbuffers_);
  }
  ViewRenderer(const ViewRenderer&) = delete;
  ViewRenderer& operator=(const ViewRenderer&) = delete;

  // Renders direction d; `ids` gets the view's rectangle, row by row: gl_PrimitiveID + 1, 0 = nothing or a back face.
  void render(const Vec3& d, std::vector<GLuint>& ids) {
    const View view = makeView(d, scene_);
    const GLuint zero[4] = {0, 0, 0, 0};
    glClearBufferuiv(GL_COLOR, 0, zero);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUniformMatrix3fv(view_location_, 1, GL_TRUE, view.rows);
    glDrawElements(GL_TRIANGLES, GLsizei(scene_.indices.size()), GL_UNSIGNED_INT, nullptr);
    ids.resize(std::size_t(view.width) * view.height);  // within the capacity reserved once: no reallocation
    glReadPixels(view.x, view.y, view.width, view.height, GL_RED_INTEGER, GL_UNSIGNED_INT, ids.data());
  }

 private:
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
};

// State the workers share. Results are merged and progress is counted under `mutex`; the calling thread alone
// calls the user's progress function.
struct Shared {
  Shared(const Scene& s, const std::vector<Vec3>& d, BitMatrix& b) : scene(s), directions(d), bits(b) {}
  const Scene& scene;
  const std::vector<Vec3>& directions;
  BitMatrix& bits;
  std::atomic<int> next{0};       // next direction to claim
  std::atomic<bool> stop{false};  // cancelled or failed
  std::mutex mutex;
  std::condition_variable changed;
  int done = 0, running = 0;
  std::exception_ptr error;
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

void renderDirections(Shared& shared) {
  OffscreenContext context;  // one per thread: OSMesa contexts are current on one thread at a time
  ViewRenderer renderer(shared.scene);
  std::vector<int> stamp(shared.scene.normals.size(), -1), visible;
  std::vector<GLuint> ids;
  ids.reserve(std::size_t(shared.scene.resolution) * shared.scene.resolution);
  const int count = static_cast<int>(shared.directions.size());
  for (int d = shared.next++; d < count && !shared.stop; d = shared.next++) {
    const Vec3 direction = shared.directions[d].normalized();
    renderer.render(direction, ids);
    collectVisible(ids, shared.scene, direction, d, stamp, visible);
    std::lock_guard<std::mutex> lock(shared.mutex);  // other threads' bits share the same 64-bit words
    for (int t : visible) shared.bits.set(t, d);
    ++shared.done;
    shared.changed.notify_all();
  }
  checkGlError("renderVisibility");
}

void worker(Shared& shared) {
  try {
    renderDirections(shared);
  } catch (...) {
    std::lock_guard<std::mutex> lock(shared.mutex);
    if (!shared.error) shared.error = std::current_exception();
    shared.stop = true;
  }
  std::lock_guard<std::mutex> lock(shared.mutex);
  --shared.running;
  shared.changed.notify_all();
}

// Waits for the workers, reporting progress from the calling thread; false when the user cancelled.
bool superviseWorkers(Shared& shared, const Progress& progress) {
  const double total = std::max<std::size_t>(shared.directions.size(), 1);
  std::unique_lock<std::mutex> lock(shared.mutex);
  int reported = -1;
  while (shared.running > 0) {
    shared.changed.wait(lock);
    if (!progress || shared.done == reported || shared.stop) continue;
    reported = shared.done;
    lock.unlock();  // the callback may be slow; workers must not wait for it
    const bool go_on = progress(reported / total);
    lock.lock();
    if (!go_on) {
      shared.stop = true;
      return false;
    }
  }
  return true;
}

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

  const Scene scene = prepareScene(mesh, options);
  Shared shared(scene, directions, map.bits);
  const int threads = threadCount(options, directions.size());
  shared.running = threads;
  std::vector<std::thread> workers;
  try {
    for (int i = 0; i < threads; ++i) workers.emplace_back(worker, std::ref(shared));
  } catch (...) {  // no thread left to start: stop the ones running before unwinding
    shared.stop = true;
    for (std::thread& w : workers) w.join();
    throw;
  }
  const bool completed = superviseWorkers(shared, progress);
  for (std::thread& w : workers) w.join();

  if (!completed) throw std::runtime_error("cancelled");
  if (shared.error) std::rethrow_exception(shared.error);
  if (progress && !progress(1.0)) throw std::runtime_error("cancelled");
  return map;
}

}  // namespace art2part
