// art2part verify DIR [--part FILE] [--resolution MM] [--tolerance MM] [--stock-margin MM] [--stock FILE]
//                     [--picture FILE.png] [--stock-out FILE.stl] [--threads N] [--units U]
// Checks DIR/toolpaths.csv with DIR/tools.json against the part (DIR/mesh.stl unless --part): the JSON report on
// stdout, exit 1 on any gouge or collision.
#include <algorithm>
#include <iostream>

#include "arguments.h"
#include "art2part/plan/plan_folder.h"
#include "art2part/geometry/mesh_io.h"
#include "art2part/simulation/part_distance.h"
#include "art2part/simulation/stock_mesh.h"
#include "art2part/simulation/verify.h"
#include "commands.h"
#include "terminal_progress.h"

namespace art2part {

namespace {

VerifyOptions verifyOptionsFrom(const Arguments& a) {
  VerifyOptions options;
  options.resolution = a.number("resolution", 0.0);
  options.tolerance = a.number("tolerance", options.tolerance);
  options.stock_margin = a.number("stock-margin", options.stock_margin);
  options.threads = a.integer("threads", 0);
  options.max_listed = a.integer("max-listed", options.max_listed);
  if (options.resolution < 0.0 || options.tolerance < 0.0 || options.stock_margin < 0.0 || options.threads < 0 ||
      options.max_listed < 0)
    throw UsageError("--resolution, --tolerance, --stock-margin, --threads and --max-listed must not be negative");
  return options;
}

// The remaining stock, contoured: a PNG coloured by deviation and/or a binary STL.
void writeStockOutputs(const Arguments& a, const Mesh& part, const VerificationState& state,
                       const VerificationReport& report) {
  if (!a.has("picture") && !a.has("stock-out")) return;
  const PartDistance distance(part);
  const StockMesh stock = remainingStockMesh(state.stock, state.part, distance);
  if (a.has("stock-out")) writeBinaryStl(stock.mesh, a.value("stock-out"), "art2part remaining stock");
  if (a.has("picture")) {
    const double scale = std::max(report.leftover_max_mm, 10.0 * report.tolerance_mm);
    writeDeviationPicture(stock, scale, report.tolerance_mm, a.value("picture"));
  }
}

}  // namespace

int runVerify(const std::vector<std::string>& args) {
  const Arguments a(args, {},
                    {"part", "resolution", "tolerance", "stock-margin", "stock", "picture", "stock-out", "threads",
                     "units", "max-listed"});
  const std::string dir = a.requirePositional(1, "one plan folder: art2part verify DIR");
  VerifyOptions options = verifyOptionsFrom(a);
  const PlanFolder folder = readPlanFolder(dir);
  const Toolpath& path = folder.toolpath;
  const std::vector<Tool>& tools = folder.tools;
  LoadOptions load;
  load.unit = parseLengthUnit(a.value("units", "auto"));
  const Part part = loadPart(a.value("part", dir + "/mesh.stl"), load);
  Mesh stock_mesh;
  if (a.has("stock")) {
    stock_mesh = loadPart(a.value("stock"), load).mesh;
    options.stock_mesh = &stock_mesh;
  }
  VerificationState state;
  const ProgressSink progress = terminalProgress();
  const VerificationReport report =
      verifyToolpath(part.mesh, part.triangle_face, path, tools, options, &state, progress);
  endTerminalProgress(progress);
  writeStockOutputs(a, part.mesh, state, report);
  std::cout << reportJson(report) << "\n";
  return report.passed() ? 0 : 1;
}

}  // namespace art2part
