#include "art2part/finishing/hole_links.h"

#include <memory>

#include "art2part/roughing/link_clearance.h"

namespace art2part {

HoleLink linkOverStock(const std::vector<SlabState>& slabs, const SetupFrame& frame, const Tool& tool, double margin) {
  auto clearance = std::make_shared<LinkClearance>(tool, margin, LinkClearance::Beside::WholeTool);
  for (const SlabState& slab : slabs) clearance->addSlab(slab, {});
  return [clearance, frame](const Vec3& from, const Vec3& to, double lowest, double level) {
    // Heights along the axis as Vec3::dot measures them; the frame's z is that less the origin's.
    const double base = frame.origin.dot(frame.z);
    const auto flat = [&frame](const Vec3& p) {
      return Point2((p - frame.origin).dot(frame.x), (p - frame.origin).dot(frame.y));
    };
    return base + clearance->lowestClear(flat(from), flat(to), lowest - base, level - base);
  };
}

}  // namespace art2part
