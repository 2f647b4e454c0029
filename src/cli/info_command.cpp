// art2part info PART [--json] [--units mm|in|m] [--tolerance MM]
#include <iostream>

#include "arguments.h"
#include "art2part/geometry/part_report.h"
#include "commands.h"

namespace art2part {

LoadOptions loadOptionsFrom(const Arguments& a) {
  LoadOptions options;
  options.unit = parseLengthUnit(a.value("units", "auto"));
  options.chordal_tolerance = a.number("tolerance", 0.0);
  if (options.chordal_tolerance < 0.0) throw UsageError("--tolerance must be positive");
  return options;
}

int runInfo(const std::vector<std::string>& args) {
  const Arguments a(args, {"json"}, {"units", "tolerance"});
  const std::string path = a.requirePositional(1, "one part file: art2part info PART");
  const Part part = loadPart(path, loadOptionsFrom(a));
  if (a.flag("json"))
    std::cout << partReport(part).dump(2) << "\n";
  else
    std::cout << partReportText(part);
  return 0;
}

}  // namespace art2part
