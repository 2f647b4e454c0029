// The visibility stage as one call: directions on the Gaussian sphere (with the part's special directions), direct
// visibility by one backend, side correction, and the figures a user wants to see.
#pragma once

#include "art2part/common/progress.h"

#include <string>

#include "art2part/geometry/part.h"
#include "art2part/sphere/direction_set.h"
#include "art2part/sphere/special_directions.h"
#include "art2part/visibility/visibility.h"

namespace art2part {

enum class VisibilityBackend { Ray, Render };
VisibilityBackend parseVisibilityBackend(const std::string& name);  // "ray" | "render"; throws InputError
const char* visibilityBackendName(VisibilityBackend backend);

struct VisibilityOptions {
  int level = 4;                       // 4 * 4^level cells (level 4: 1024 directions)
  SphereBase base = SphereBase::Tetrahedron;
  bool special_directions = true;
  SpecialDirectionOptions special;
  VisibilityBackend backend = VisibilityBackend::Ray;
  bool side_correction = true;
  RenderVisibilityOptions render;
  RayVisibilityOptions ray = defaultRayOptions();  // closer to "some point visible" than the bare samples
  int threads = 0;                     // 0 = every hardware thread
};

struct VisibilityResult {
  DirectionSet directions;
  VisibilityMap map;
  int special_directions = 0;          // how many of the directions are special
  long long side_pairs_added = 0;      // by side correction
  std::vector<int> unseen_triangles;   // visible along no direction at all
  double seconds_directions = 0, seconds_visibility = 0, seconds_side = 0;
  bool cancelled = false;              // the progress sink asked to stop: the map is incomplete, do not use it
};

// Reports ("visibility", the share of the directions done, what it does) to `progress` as the backend goes, and stops
// when it says so (cancelled set, nothing thrown). Throws InputError for bad options (level out of 0..7).
VisibilityResult analyseVisibility(const Part& part, const VisibilityOptions& options = {},
                                   const ProgressSink& progress = {});

// The files of the contract `art2part visibility`: mesh.stl, directions.csv (x,y,z a line), visibility.bits.
void writeVisibilityFiles(const Part& part, const VisibilityResult& result, const std::string& folder);

}  // namespace art2part
