// The art2part sub-commands. Each returns the process exit status; InputError and UsageError are reported by main().
#pragma once

#include <set>
#include <string>
#include <vector>

#include "art2part/geometry/part.h"

namespace art2part {

struct VisibilityOptions;
struct SetupOptions;

LoadOptions loadOptionsFrom(const class Arguments& a);  // --units, --tolerance
// --level, --sphere, --backend, --no-special, --no-side, --resolution, --samples, --threads (visibility_command.cpp)
VisibilityOptions visibilityOptionsFrom(const Arguments& a);
// --mode, --tilt, --time-limit, --no-pp (setups_command.cpp); and every flag and option `setups` and `plan` share.
SetupOptions setupOptionsFrom(const Arguments& a);
const std::set<std::string>& setupFlags();
const std::set<std::string>& setupValueOptions();
int runInfo(const std::vector<std::string>& args);
int runRender(const std::vector<std::string>& args);
int runVisibility(const std::vector<std::string>& args);
int runSetups(const std::vector<std::string>& args);
int runPlan(const std::vector<std::string>& args);
int runVerify(const std::vector<std::string>& args);
int runPost(const std::vector<std::string>& args);
int runUrdf(const std::vector<std::string>& args);  // urdf_command.cpp

}  // namespace art2part
