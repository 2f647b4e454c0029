// The art2part sub-commands. Each returns the process exit status; InputError and UsageError are reported by main().
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/part.h"

namespace art2part {

LoadOptions loadOptionsFrom(const class Arguments& a);  // --units, --tolerance
int runInfo(const std::vector<std::string>& args);
int runRender(const std::vector<std::string>& args);
int runVisibility(const std::vector<std::string>& args);

}  // namespace art2part
