#include "arguments.h"

#include <cmath>
#include <stdexcept>

namespace art2part {

double parseNumber(const std::string& text, const std::string& what) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {  // not a number at all, or out of a double's range
  }
  throw UsageError(what + " needs a number, not '" + text + "'");
}

int parseInteger(const std::string& text, const std::string& what) {
  try {
    std::size_t used = 0;
    const int v = std::stoi(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {  // not a number at all, or out of an int's range
  }
  throw UsageError(what + " needs a whole number, not '" + text + "'");
}

Arguments::Arguments(const std::vector<std::string>& args, const std::set<std::string>& flags,
                     const std::set<std::string>& options) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) != 0 || a == "--") {
      positional_.push_back(a);
      continue;
    }
    const std::string name = a.substr(2);
    if (flags.count(name)) {
      flags_.insert(name);
    } else if (options.count(name)) {
      if (i + 1 >= args.size()) throw UsageError("option " + a + " needs a value");
      values_[name] = args[++i];
    } else {
      throw UsageError("unknown option " + a);
    }
  }
}

std::string Arguments::value(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

double Arguments::number(const std::string& name, double fallback) const {
  return has(name) ? parseNumber(value(name), "--" + name) : fallback;
}

int Arguments::integer(const std::string& name, int fallback) const {
  return has(name) ? parseInteger(value(name), "--" + name) : fallback;
}

std::string Arguments::requirePositional(std::size_t count, const std::string& names) const {
  if (positional_.size() != count) throw UsageError("expected " + names);
  return positional_.front();
}

}  // namespace art2part
