// Pieces shared by the setup sources (not part of the library's interface).
#pragma once

#include <functional>
#include <vector>

#include "art2part/setup/setup_plan.h"
#include "art2part/visibility/cones.h"

namespace art2part::setup_detail {

// A flat face that some direction sees whole and square (3.3.2): the "2" entries of the multi-valued matrix.
struct SquareFace {
  int face = -1;
  Cone earners;  // the directions that see every triangle of the face and meet it square
};

// Every plane face with at least one earner, in face order. Empty when options.parallel_perpendicular is false.
std::vector<SquareFace> squareFaces(const Part& part, const VisibilityResult& visibility,
                                    const std::vector<std::vector<int>>& face_triangles, const SetupOptions& options);

// The cover problem over a reach matrix (moved in), with the square faces as bonus items weighted by area.
CoverProblem coverProblemOf(BitMatrix reach, const std::vector<SquareFace>& square_faces, const Part& part);

// The setups from the cover problem, preferring (fewest setups, most special directions, most bonus): the plain
// minimum cover proves the size; a cover of special directions alone of that size with the most bonus is taken when
// there is one, otherwise the plain cover improved by swapping single directions. proven_minimal refers to the size;
// bonus_proven_best to the best bonus among covers of special directions only. stats: the plain search.
// keep_going: as CoverOptions::keep_going, for both searches (the second is skipped once it says stop).
CoverResult chooseSetups(const CoverProblem& problem, const std::vector<char>& special, const SetupOptions& options,
                         const std::function<bool()>& keep_going = {});

// Throws InputError when the visibility result does not belong to the part or an option is out of range.
void checkSetupInputs(const Part& part, const VisibilityResult& visibility, const SetupOptions& options);

// What the chosen setups machine: per chosen setup (same order as `chosen`) its faces and triangles, plus the faces
// no chosen setup reaches whole. Faces go, largest first, to the setup that reaches all of them, earns their square
// bonus and meets them most head-on (largest area-weighted n . d); a split face's triangles go one by one.
struct Assignment {
  std::vector<std::vector<int>> faces, triangles;  // ascending
  std::vector<int> split_faces;                     // ascending
};

Assignment assignToSetups(const Part& part, const std::vector<std::vector<int>>& face_triangles,
                          const BitMatrix& reach, const std::vector<Vec3>& directions, const std::vector<int>& chosen,
                          const std::vector<SquareFace>& square_faces);

}  // namespace art2part::setup_detail
