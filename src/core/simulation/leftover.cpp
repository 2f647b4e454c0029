#include "art2part/simulation/leftover.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace art2part {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kGrazing = 0.25;       // |n . ray| below this (75 degrees off the normal): the crossing is ignored
constexpr double kCuspAlignment = 0.5;  // rays within 60 degrees of a face's normal sample its cusps
constexpr int kSamplesPerSpan = 16;     // lattice points measured along one leftover span, at most

// Distances from t along one ray to the part's surface on either side: weighted by |n . ray| (tangent plane) and raw.
struct RayDistance {
  double tangent = kInfinity, raw = kInfinity;
};

RayDistance distanceAlongRay(const MeshDexels& part, int axis, int ray, double t) {
  RayDistance d;
  auto weigh = [&](double along, int triangle) {
    d.raw = std::min(d.raw, along);
    const double c = std::abs(part.normals()[triangle][axis]);
    if (c >= kGrazing) d.tangent = std::min(d.tangent, along * c);
  };
  const SolidSpan* below = nullptr;
  for (const SolidSpan* s = part.begin(axis, ray); s != part.end(axis, ray); ++s) {
    if (s->hi <= t) {
      below = s;
      continue;
    }
    if (s->lo < t) return {0.0, 0.0};  // inside the part
    weigh(s->lo - t, s->lo_triangle);
    break;
  }
  if (below) weigh(t - below->hi, below->hi_triangle);
  return d;
}

double boxDistance(const Box& box, const Vec3& p) {
  return ((box.min - p).cwiseMax(0.0) + (p - box.max).cwiseMax(0.0)).norm();
}

// Thickness of leftover at the lattice point (i, j, l): the least over the three rays through it.
double latticeThickness(const MeshDexels& part, const Box& part_box, int i, int j, int l) {
  const DexelLattice& lattice = part.lattice();
  const Vec3 p(lattice.coordinate(0, i), lattice.coordinate(1, j), lattice.coordinate(2, l));
  const RayDistance along[3] = {distanceAlongRay(part, 0, lattice.rayIndex(0, j, l), p.x()),
                                distanceAlongRay(part, 1, lattice.rayIndex(1, l, i), p.y()),
                                distanceAlongRay(part, 2, lattice.rayIndex(2, i, j), p.z())};
  double tangent = kInfinity, raw = kInfinity;
  for (const RayDistance& d : along) {
    tangent = std::min(tangent, d.tangent);
    raw = std::min(raw, d.raw);
  }
  if (tangent < kInfinity) return tangent;
  return raw < kInfinity ? raw : boxDistance(part_box, p);
}

SpanList leftoverOnRay(const Stock& stock, const MeshDexels& part, int axis, int ray, double noise) {
  SpanList out = spanDifference(stock.ray(axis, ray), part.spans(axis, ray));
  out.erase(std::remove_if(out.begin(), out.end(), [&](const Span& s) { return s.length() <= noise; }), out.end());
  return out;
}

double leftoverVolume(const Stock& stock, const MeshDexels& part, double noise) {
  double sum = 0;
  for (int axis = 0; axis < 3; ++axis) {
    double length = 0;
    for (int ray = 0; ray < stock.lattice.rayCount(axis); ++ray)
      length += totalLength(leftoverOnRay(stock, part, axis, ray, noise));
    sum += length * stock.lattice.cellArea(axis);
  }
  return sum / 3.0;
}

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Joins the overlapping spans of two neighbouring rays.
void joinRays(std::vector<int>& parent, const std::vector<Span>& spans, int a0, int a1, int b0, int b1) {
  for (int a = a0, b = b0; a < a1 && b < b1;) {
    if (spans[a].lo < spans[b].hi && spans[b].lo < spans[a].hi) parent[findRoot(parent, a)] = findRoot(parent, b);
    if (spans[a].hi < spans[b].hi) ++a;
    else ++b;
  }
}

// The thickest lattice point of a z span (its middle, by the z ray alone, when no lattice point lies inside). Long
// spans are sampled at kSamplesPerSpan points, ends included: thickness changes by at most the distance moved.
double spanThickness(const MeshDexels& part, const Box& part_box, int i, int j, const Span& s, Vec3& where) {
  const DexelLattice& lattice = part.lattice();
  const auto ls = lattice.indexRange(2, s.lo, s.hi);
  double best = -1;
  const int stride = std::max(1, (ls[1] - ls[0] + kSamplesPerSpan) / kSamplesPerSpan);
  for (int l = ls[0]; l <= ls[1]; l = l < ls[1] ? std::min(l + stride, ls[1]) : l + 1) {
    const double t = latticeThickness(part, part_box, i, j, l);
    if (t > best) {
      best = t;
      where = Vec3(lattice.coordinate(0, i), lattice.coordinate(1, j), lattice.coordinate(2, l));
    }
  }
  if (best >= 0) return best;
  where = Vec3(lattice.coordinate(0, i), lattice.coordinate(1, j), 0.5 * (s.lo + s.hi));
  const RayDistance d = distanceAlongRay(part, 2, lattice.rayIndex(2, i, j), where.z());
  return d.tangent < kInfinity ? d.tangent : (d.raw < kInfinity ? d.raw : boxDistance(part_box, where));
}

std::vector<LeftoverRegion> leftoverRegions(const Stock& stock, const MeshDexels& part, const Box& part_box,
                                            double noise) {
  const DexelLattice& lattice = stock.lattice;
  const int nu = lattice.cells[0], nv = lattice.cells[1];
  std::vector<Span> spans;
  std::vector<int> offsets(lattice.rayCount(2) + 1, 0);
  for (int ray = 0; ray < lattice.rayCount(2); ++ray) {
    offsets[ray] = static_cast<int>(spans.size());
    for (const Span& s : leftoverOnRay(stock, part, 2, ray, noise)) spans.push_back(s);
  }
  offsets.back() = static_cast<int>(spans.size());
  std::vector<int> parent(spans.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int ray = lattice.rayIndex(2, i, j);
      if (i + 1 < nu) joinRays(parent, spans, offsets[ray], offsets[ray + 1], offsets[ray + 1], offsets[ray + 2]);
      if (j + 1 < nv)
        joinRays(parent, spans, offsets[ray], offsets[ray + 1], offsets[ray + nu], offsets[ray + nu + 1]);
    }
  std::vector<int> region_of(spans.size(), -1);
  std::vector<LeftoverRegion> regions;
  const Vec3 half = 0.5 * lattice.spacing;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int ray = lattice.rayIndex(2, i, j);
      for (int k = offsets[ray]; k < offsets[ray + 1]; ++k) {
        const int root = findRoot(parent, k);
        if (region_of[root] < 0) {
          region_of[root] = static_cast<int>(regions.size());
          regions.emplace_back();
        }
        LeftoverRegion& region = regions[region_of[root]];
        const Span& s = spans[k];
        region.volume_mm3 += s.length() * lattice.cellArea(2);
        Vec3 where;
        const double thickness = spanThickness(part, part_box, i, j, s, where);
        if (thickness > region.max_thickness_mm) {
          region.max_thickness_mm = thickness;
          region.thickest_point = where;
        }
        const Vec3 centre(lattice.coordinate(0, i), lattice.coordinate(1, j), 0.0);
        region.box.extend(Vec3(centre.x() - half.x(), centre.y() - half.y(), s.lo));
        region.box.extend(Vec3(centre.x() + half.x(), centre.y() + half.y(), s.hi));
      }
    }
  std::sort(regions.begin(), regions.end(),
            [](const LeftoverRegion& a, const LeftoverRegion& b) { return a.volume_mm3 > b.volume_mm3; });
  return regions;
}

// Leftover met just outside the part's surface at t along the ray, leaving the part towards -ray (entry) or +ray.
double leftoverBeside(const SpanList& stock, const SolidSpan* previous, const SolidSpan* next, double t, bool entry,
                      double noise) {
  for (const Span& s : stock) {
    if (entry && s.lo < t - noise && s.hi >= t - noise) return t - std::max(s.lo, previous ? previous->hi : s.lo);
    if (!entry && s.lo <= t + noise && s.hi > t + noise) return std::min(s.hi, next ? next->lo : s.hi) - t;
  }
  return 0.0;
}

std::vector<FaceCusp> faceCusps(const Stock& stock, const MeshDexels& part, const std::vector<int>& triangle_face,
                                double noise) {
  const int faces = triangle_face.empty() ? 0 : *std::max_element(triangle_face.begin(), triangle_face.end()) + 1;
  std::vector<FaceCusp> cusps(std::max(faces, 0));
  auto sample = [&](int triangle, int axis, double along) {
    if (triangle < 0 || triangle >= static_cast<int>(triangle_face.size()) || triangle_face[triangle] < 0) return;
    const double c = std::abs(part.normals()[triangle][axis]);
    if (c < kCuspAlignment) return;
    FaceCusp& f = cusps[triangle_face[triangle]];
    f.max_mm = std::max(f.max_mm, along * c);
    f.mean_mm += along * c;
    ++f.samples;
  };
  for (int axis = 0; axis < 3 && faces > 0; ++axis)
    for (int ray = 0; ray < stock.lattice.rayCount(axis); ++ray) {
      const SolidSpan *first = part.begin(axis, ray), *last = part.end(axis, ray);
      for (const SolidSpan* p = first; p != last; ++p) {
        const SolidSpan* previous = p == first ? nullptr : p - 1;
        const SolidSpan* next = p + 1 == last ? nullptr : p + 1;
        const SpanList& material = stock.ray(axis, ray);
        sample(p->lo_triangle, axis, leftoverBeside(material, previous, next, p->lo, true, noise));
        sample(p->hi_triangle, axis, leftoverBeside(material, previous, next, p->hi, false, noise));
      }
    }
  std::vector<FaceCusp> out;
  for (int f = 0; f < faces; ++f)
    if (cusps[f].samples > 0) {
      cusps[f].face = f;
      cusps[f].mean_mm /= cusps[f].samples;
      out.push_back(cusps[f]);
    }
  return out;
}

}  // namespace

LeftoverAnalysis analyseLeftover(const Stock& stock, const MeshDexels& part, const Box& part_box,
                                 const std::vector<int>& triangle_face, double noise_mm) {
  LeftoverAnalysis a;
  a.volume_mm3 = leftoverVolume(stock, part, noise_mm);
  a.regions = leftoverRegions(stock, part, part_box, noise_mm);
  for (const LeftoverRegion& r : a.regions) a.max_thickness_mm = std::max(a.max_thickness_mm, r.max_thickness_mm);
  a.faces = faceCusps(stock, part, triangle_face, noise_mm);
  return a;
}

}  // namespace art2part
