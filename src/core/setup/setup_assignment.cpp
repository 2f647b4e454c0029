// Which chosen setup machines what: whole faces where one setup reaches them (preferring the setup that meets the
// face square and head-on), the triangles of split faces one by one.
#include <algorithm>
#include <numeric>

#include "setup_internal.h"

namespace art2part::setup_detail {
namespace {

bool reachesAll(const BitMatrix& reach, const std::vector<int>& triangles, int direction) {
  for (int t : triangles)
    if (!reach.get(t, direction)) return false;
  return true;
}

// Sum of area times unit normal: its dot product with a direction is the face's area-weighted n . d times its area.
Vec3 areaNormal(const Mesh& mesh, const std::vector<int>& triangles) {
  Vec3 sum = Vec3::Zero();
  for (int t : triangles) sum += triangleArea(mesh, t) * triangleNormal(mesh, t);
  return sum;
}

// Faces largest first (by index among equals): big faces claim their setup before small ones.
std::vector<int> facesByArea(const std::vector<Face>& faces) {
  std::vector<int> order(faces.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return faces[a].area > faces[b].area; });
  return order;
}

class Assigner {
 public:
  Assigner(const Part& part, const BitMatrix& reach, const std::vector<Vec3>& directions,
           const std::vector<int>& chosen, const std::vector<SquareFace>& square_faces)
      : part_(part), reach_(reach), directions_(directions), chosen_(chosen), square_of_(part.faces.size(), -1),
        square_faces_(square_faces) {
    for (int i = 0; i < static_cast<int>(square_faces.size()); ++i) square_of_[square_faces[i].face] = i;
    out_.faces.resize(chosen.size());
    out_.triangles.resize(chosen.size());
  }

  // The chosen setup that reaches every triangle of face f, earning its square bonus first, then most head-on; -1 if
  // none reaches it whole.
  int setupForFace(int f, const std::vector<int>& triangles) const {
    const Vec3 area_normal = areaNormal(part_.mesh, triangles);
    int best = -1;
    bool best_earns = false;
    double best_nz = 0.0;
    for (int k = 0; k < static_cast<int>(chosen_.size()); ++k) {
      const int d = chosen_[k];
      if (!reachesAll(reach_, triangles, d)) continue;
      const bool earns = square_of_[f] >= 0 && coneHas(square_faces_[square_of_[f]].earners, d);
      const double nz = area_normal.dot(directions_[d]);
      if (best < 0 || earns > best_earns || (earns == best_earns && nz > best_nz)) {
        best = k;
        best_earns = earns;
        best_nz = nz;
      }
    }
    return best;
  }

  // The chosen setup reaching triangle t that meets it most head-on; -1 when none reaches it (unmachinable).
  int setupForTriangle(int t) const {
    const Vec3 n = triangleNormal(part_.mesh, t);
    int best = -1;
    double best_nz = 0.0;
    for (int k = 0; k < static_cast<int>(chosen_.size()); ++k) {
      const int d = chosen_[k];
      if (!reach_.get(t, d)) continue;
      const double nz = n.dot(directions_[d]);
      if (best < 0 || nz > best_nz) best = k, best_nz = nz;
    }
    return best;
  }

  void assignFace(int f, const std::vector<int>& triangles) {
    const int k = setupForFace(f, triangles);
    if (k >= 0) {
      out_.faces[k].push_back(f);
      out_.triangles[k].insert(out_.triangles[k].end(), triangles.begin(), triangles.end());
      return;
    }
    out_.split_faces.push_back(f);
    for (int t : triangles) assignTriangle(t);
  }

  void assignTriangle(int t) {
    const int k = setupForTriangle(t);
    if (k >= 0) out_.triangles[k].push_back(t);
  }

  Assignment finish() {
    for (auto& v : out_.faces) std::sort(v.begin(), v.end());
    for (auto& v : out_.triangles) std::sort(v.begin(), v.end());
    std::sort(out_.split_faces.begin(), out_.split_faces.end());
    return std::move(out_);
  }

 private:
  const Part& part_;
  const BitMatrix& reach_;
  const std::vector<Vec3>& directions_;
  const std::vector<int>& chosen_;
  std::vector<int> square_of_;  // per face: its index in square_faces_, or -1
  const std::vector<SquareFace>& square_faces_;
  Assignment out_;
};

}  // namespace

Assignment assignToSetups(const Part& part, const std::vector<std::vector<int>>& face_triangles,
                          const BitMatrix& reach, const std::vector<Vec3>& directions, const std::vector<int>& chosen,
                          const std::vector<SquareFace>& square_faces) {
  Assigner assigner(part, reach, directions, chosen, square_faces);
  for (int f : facesByArea(part.faces))
    if (!face_triangles[f].empty()) assigner.assignFace(f, face_triangles[f]);
  for (int t = 0; t < part.mesh.triangleCount(); ++t) {  // triangles of no face
    const int f = part.triangle_face[t];
    if (f < 0 || f >= static_cast<int>(part.faces.size())) assigner.assignTriangle(t);
  }
  return assigner.finish();
}

}  // namespace art2part::setup_detail
