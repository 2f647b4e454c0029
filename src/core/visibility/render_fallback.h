// Private to render_visibility.cpp: rays for what a view's pixels cannot resolve.
//
// A triangle thinner than a pixel wins no pixel centre and its outline, drawn inside it, often loses the depth test
// to its neighbours' fill; a visible piece smaller than a pixel (a corner peeking out from under an occluder) shows in
// no pixel at all. The exact oracle (exact_visibility.h) finds these visible on CAD tessellations in 1-3% of all
// pairs. So after each view the renderer asks rays about exactly those: every front-facing triangle thinner than a
// few pixels that no pixel showed, from its interior sample points, and, spreading out from the triangles the view
// did show, the hidden front-facing neighbours, from points just inside the shared edge. A triangle the pixels
// resolve and no visible neighbour touches keeps the pixels' answer.
#pragma once

#include <memory>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part::idrender {

class RayFallback {
 public:
  // pixel: the width of a view's pixel in the mesh's units.
  RayFallback(const Mesh& mesh, double pixel);
  ~RayFallback();
  RayFallback(const RayFallback&) = delete;
  RayFallback& operator=(const RayFallback&) = delete;

  // One worker's buffers; the scene is shared and read-only.
  class Tracer {
   public:
    explicit Tracer(const RayFallback& fallback);
    ~Tracer();
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    // visible: the triangles the view showed along unit d (front-facing); adds those the rays find.
    void complete(const Vec3& d, std::vector<int>& visible);

   private:
    struct State;
    std::unique_ptr<State> state_;
  };

 private:
  struct Shared;
  std::unique_ptr<Shared> shared_;
};

}  // namespace art2part::idrender
