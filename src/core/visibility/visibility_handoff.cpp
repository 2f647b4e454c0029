// A visibility result handed on in the file contract's layout (visibility_handoff.h).
#include "art2part/visibility/visibility_handoff.h"

#include <cmath>
#include <cstdio>
#include <cstring>

#include "art2part/sphere/special_directions.h"
#include "art2part/visibility/cones.h"

namespace art2part {

namespace {

constexpr int kMaxLevel = 7;             // what analyseVisibility accepts
constexpr double kUnitTolerance = 1e-6;  // a direction further than this from unit length is refused

std::string fmt(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// sampleSphere(level) with `directions` as its directions when they are what analyseVisibility makes of it (each
// cell's own direction lies in that cell, the extras after them lie in some cell); otherwise an empty set.
DirectionSet sphereFor(const std::vector<Vec3>& directions) {
  const int count = static_cast<int>(directions.size());
  for (int level = kMaxLevel; level >= 0; --level) {
    if ((4LL << (2 * level)) > count) continue;
    DirectionSet set = sampleSphere(level);
    const int cells = set.cellCount();
    set.cell_of.resize(count);
    bool consistent = true;
    for (int d = 0; d < count && consistent; ++d) {
      const int c = cellContaining(set, directions[d]);
      if (d < cells) consistent = c == d;
      else set.cell_of[d] = c;
    }
    if (consistent) return set;
  }
  return DirectionSet{};
}

// Special flags by matching the part's special directions (made, and so compared, exactly as analyseVisibility does).
std::vector<char> matchSpecial(const Part& part, const std::vector<Vec3>& directions) {
  std::vector<char> special(directions.size(), 0);
  const std::vector<SpecialDirection> found = specialDirections(part);
  for (std::size_t d = 0; d < directions.size(); ++d)
    for (const SpecialDirection& s : found)
      if (s.direction.norm() > 0 && directions[d].dot(s.direction.normalized()) >= 1.0 - 1e-12) {
        special[d] = 1;
        break;
      }
  return special;
}

}  // namespace

VisibilityResult visibilityFromBits(const Part& part, const std::vector<Vec3>& given_directions,
                                    const std::vector<std::uint8_t>& bits, const std::vector<std::uint8_t>& special_flags) {
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "bits are copied into 64-bit words byte by byte");
  const int D = static_cast<int>(given_directions.size());
  const int T = part.mesh.triangleCount();
  if (D == 0) throw InputError("bits or special flags given without directions");

  std::vector<Vec3> directions(D);
  for (int d = 0; d < D; ++d) {
    const Vec3& u = given_directions[d];
    if (!u.allFinite() || std::abs(u.norm() - 1.0) > kUnitTolerance)
      throw InputError("direction " + std::to_string(d) + " (" + fmt(u.x()) + ", " + fmt(u.y()) + ", " + fmt(u.z()) +
                       ") is not a unit vector");
    directions[d] = std::abs(u.squaredNorm() - 1.0) < 1e-15 ? u : u.normalized();  // the analysis' own, unchanged
  }

  const std::size_t bytes = (static_cast<std::size_t>(D) + 7) / 8;
  if (bits.size() != static_cast<std::size_t>(T) * bytes)
    throw InputError("bits: " + std::to_string(bits.size()) + " bytes, but the part's " + std::to_string(T) +
                     " triangles x ceil(" + std::to_string(D) + " directions / 8) need " +
                     std::to_string(static_cast<std::size_t>(T) * bytes) +
                     " (a visibility result of another part or level?)");
  if (!special_flags.empty() && special_flags.size() != static_cast<std::size_t>(D))
    throw InputError("special: " + std::to_string(special_flags.size()) + " flags for " + std::to_string(D) +
                     " directions");

  VisibilityResult result;
  result.directions = sphereFor(directions);
  result.directions.directions = directions;
  if (special_flags.empty()) {
    result.directions.special = matchSpecial(part, directions);
  } else {
    result.directions.special.resize(D);
    for (int d = 0; d < D; ++d) result.directions.special[d] = special_flags[d] ? 1 : 0;
  }
  for (char s : result.directions.special) result.special_directions += s;

  result.map.bits = BitMatrix(T, D);
  const int words = result.map.bits.wordsPerRow();
  const std::uint64_t last_word_mask = D % 64 == 0 ? ~std::uint64_t(0) : (std::uint64_t(1) << (D % 64)) - 1;
  for (int t = 0; t < T; ++t) {
    std::uint64_t* row = result.map.bits.row(t);
    std::memcpy(row, &bits[static_cast<std::size_t>(t) * bytes], bytes);
    row[words - 1] &= last_word_mask;  // padding bits of the last byte are not directions
  }
  result.unseen_triangles = invisibleTriangles(result.map);
  return result;
}

}  // namespace art2part
