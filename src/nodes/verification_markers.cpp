#include "verification_markers.h"

#include "marker_helpers.h"

#include "art2part/plan/plan_folder.h"
#include "art2part/plan/stage_records.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "art2part/common/request_limits.h"
#include "art2part/simulation/part_distance.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"
#include "part_conversions.h"

namespace art2part {

namespace {

std::string fmt(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// A request's optional size in mm: 0 keeps the default; outside the range (request_limits.h) is refused.
double sizeOr(double value, double fallback, const RequestRange& range) {
  return checkedRequestValue(value, range) > 0 ? value : fallback;
}

std_msgs::ColorRGBA colour(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

}  // namespace

// ---- the request -------------------------------------------------------------------------------------------------

VerifyOptions verifyOptionsFrom(const VerifyToolpathsRequest& request) {
  VerifyOptions options;
  options.resolution = sizeOr(request.resolution, 0.0, request_limits::kVerifyResolution);
  options.tolerance = sizeOr(request.tolerance, options.tolerance, request_limits::kVerifyTolerance);
  options.stock_margin = sizeOr(request.stock_margin, options.stock_margin, request_limits::kStockMargin);
  return options;
}

std::string partFileOf(const VerifyToolpathsRequest& request) {
  return request.part_file.empty() ? request.folder + "/mesh.stl" : request.part_file;
}

void verifyFolder(const VerifyToolpathsRequest& request, FolderVerification& out) {
  const VerifyOptions options = verifyOptionsFrom(request);
  if (request.folder.empty()) throw InputError("folder is empty: name a plan folder with toolpaths.csv and tools.json");
  const PlanFolder folder = readPlanFolder(request.folder);
  out.part = loadPart(partFileOf(request));
  out.report = verifyToolpath(out.part.mesh, out.part.triangle_face, folder.toolpath, folder.tools, options, &out.state);
}

void verifyHandedOn(const VerifyToolpathsRequest& request, const Part& part, FolderVerification& out) {
  const VerifyOptions options =
      request.options_record.empty() ? verifyOptionsFrom(request) : verifyOptionsFromRecord(request.options_record);
  const ToolpathAndTools plan = toolpathFromRecord(request.toolpath_record);
  if (plan.path.empty()) throw InputError("toolpath_record holds no toolpath");
  out.part = part;
  out.report = verifyToolpath(out.part.mesh, out.part.triangle_face, plan.path, plan.tools, options, &out.state);
}

// ---- the response ------------------------------------------------------------------------------------------------

void fillResponse(const VerificationReport& report, VerifyToolpathsResponse& response) {
  response.passed = report.passed();
  response.gouges = report.gouges;
  response.worst_gouge_mm = report.worst_gouge_mm;
  response.collisions = report.collisions;
  response.leftover_volume_mm3 = report.leftover_volume_mm3;
  response.leftover_max_mm = report.leftover_max_mm;
  response.moves = report.moves;
  response.report_json = reportJson(report);
  response.record = verificationRecord(report);
}

std::string summaryOf(const VerificationReport& report) {
  return std::string(report.passed() ? "passed" : "FAILED") + ": " + std::to_string(report.gouges) + " gouges" +
         (report.gouges > 0 ? " (worst " + fmt(report.worst_gouge_mm) + " mm)" : "") + ", " +
         std::to_string(report.collisions) + " collisions" +
         (report.collisions > 0 ? " (worst " + fmt(report.worst_collision_mm) + " mm)" : "") + "; leftover " +
         fmt(report.leftover_volume_mm3) + " mm3, up to " + fmt(report.leftover_max_mm) + " mm thick; " +
         std::to_string(report.moves) + " moves at " + fmt(report.resolution_mm) + " mm resolution";
}

// ---- rviz --------------------------------------------------------------------------------------------------------

StockMesh remainingStock(const FolderVerification& verification, int max_cells) {
  const PartDistance distance(verification.part.mesh);
  return remainingStockMesh(verification.state.stock, verification.state.part, distance, max_cells);
}

visualization_msgs::MarkerArray verificationMarkers(const StockMesh& stock, const VerificationReport& report,
                                                    const std::string& frame_id) {
  visualization_msgs::MarkerArray array;
  array.markers.push_back(deleteAllMarker(frame_id));

  const int T = stock.mesh.triangleCount();
  if (T > 0) {
    const double scale = std::max(report.leftover_max_mm, 10.0 * report.tolerance_mm);
    const auto colours = deviationColours(stock.deviation, scale, report.tolerance_mm);
    auto surface = baseMarker(frame_id, "remaining_stock", 0, visualization_msgs::Marker::TRIANGLE_LIST);
    surface.points.reserve(3 * static_cast<std::size_t>(T));
    surface.colors.reserve(3 * static_cast<std::size_t>(T));
    for (int t = 0; t < T; ++t) {
      const auto& rgb = t < static_cast<int>(colours.size()) ? colours[t] : std::array<unsigned char, 3>{128, 128, 128};
      const std_msgs::ColorRGBA c = colour(rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f);
      for (int k = 0; k < 3; ++k) {
        surface.points.push_back(toPointMsg(stock.mesh.corner(t, k)));
        surface.colors.push_back(c);
      }
    }
    array.markers.push_back(surface);
  }

  // Spheres big enough to find: a few lattice cells, and at least 1/100 of the stock's diagonal.
  const double diameter_mm = std::max({4.0 * report.resolution_mm, 0.01 * report.stock_box.diagonal(), 0.1});
  auto spheres = [&](const std::string& ns, const std_msgs::ColorRGBA& c, const auto& records) {
    if (records.empty()) return;
    auto m = baseMarker(frame_id, ns, 0, visualization_msgs::Marker::SPHERE_LIST);
    m.scale.x = m.scale.y = m.scale.z = diameter_mm * kMetresPerMm;
    m.color = c;
    for (const auto& r : records) m.points.push_back(toPointMsg(r.position));
    array.markers.push_back(m);
  };
  spheres("gouges", colour(0.9f, 0.05f, 0.05f), report.gouge_list);
  spheres("collisions", colour(1.0f, 0.55f, 0.0f), report.collision_list);
  return array;
}

}  // namespace art2part
