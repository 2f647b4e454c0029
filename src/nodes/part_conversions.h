// Core part <-> ROS messages. The core works in mm; messages in metres (REP 103).
#pragma once

#include <art2part/LoadedPart.h>
#include <art2part/PartSummary.h>

#include "art2part/geometry/part.h"

namespace art2part {

constexpr double kMetresPerMm = 1e-3;

// A point in mm of the core as a message point in metres.
geometry_msgs::Point toPointMsg(const Vec3& mm);

PartSummary toSummaryMsg(const Part& part);
LoadedPart toMsg(const Part& part, const std::string& id);
// Rebuilds the core part from a message (adjacency and checks recomputed). Throws InputError on a malformed message.
Part fromMsg(const LoadedPart& msg);

}  // namespace art2part
