// The benches' common command line. Each bench/*.cpp is its own executable, so this is a header (a .cpp here would
// be built as one more bench). The rule for every bench:
//   --help or -h      the usage on stdout, exit 0
//   a usage mistake   (an unknown --option, a missing or ill-formed value, an argument too many): the mistake and
//                     the usage on stderr, exit 2
//   bad input         (a part that is not there or does not load, any other error): one line "bench_x: what" on
//                     stderr, exit 1
// Nothing escapes main: no abort. Each bench checks its arguments (and that its part files are there) before any
// work starts, so a mistake costs no minutes.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "art2part/geometry/mesh.h"  // InputError

namespace art2part {

// A mistake in how the bench was called: runBench prints it with the usage and exits 2.
struct BenchUsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// `text` as a finite number, or a usage mistake naming `what` (std::atof would take garbage for 0).
inline double parseNumber(const std::string& text, const std::string& what) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw BenchUsageError(what + " needs a number, not '" + text + "'");
}

// `text` as a whole number (an int), or a usage mistake naming `what`.
inline int parseInteger(const std::string& text, const std::string& what) {
  try {
    std::size_t used = 0;
    const int v = std::stoi(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  throw BenchUsageError(what + " needs a whole number, not '" + text + "'");
}

// `value` if it is at least `least`, else a usage mistake naming `what`.
inline int atLeast(int value, int least, const std::string& what) {
  if (value < least) throw BenchUsageError(what + " must be at least " + std::to_string(least));
  return value;
}

// `value` if it is above 0, else a usage mistake naming `what`.
inline double positive(double value, const std::string& what) {
  if (!(value > 0)) throw BenchUsageError(what + " must be positive");
  return value;
}

// A bench's arguments: positional ones, --flag and --option VALUE in any order. Any other argument starting with
// "--" is a usage mistake, not a part name.
class BenchArgs {
 public:
  BenchArgs(const std::vector<std::string>& args, const std::set<std::string>& flags,
            const std::set<std::string>& options) {
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& a = args[i];
      const std::string name = a.size() > 2 && a.rfind("--", 0) == 0 ? a.substr(2) : "";
      if (name.empty()) {
        positional_.push_back(a);
      } else if (flags.count(name)) {
        flags_.insert(name);
      } else if (!options.count(name)) {
        throw BenchUsageError("unknown option " + a);
      } else if (i + 1 == args.size()) {
        throw BenchUsageError("option " + a + " needs a value");
      } else {
        values_[name] = args[++i];
      }
    }
  }

  // The positional arguments, at most `most` of them (else a usage mistake).
  const std::vector<std::string>& positional(std::size_t most = std::numeric_limits<std::size_t>::max()) const {
    if (positional_.size() > most) throw BenchUsageError("unexpected argument '" + positional_[most] + "'");
    return positional_;
  }
  bool flag(const std::string& name) const { return flags_.count(name) > 0; }
  double number(const std::string& name, double fallback) const {
    const auto it = values_.find(name);
    return it == values_.end() ? fallback : parseNumber(it->second, "--" + name);
  }
  int integer(const std::string& name, int fallback) const {
    const auto it = values_.find(name);
    return it == values_.end() ? fallback : parseInteger(it->second, "--" + name);
  }

 private:
  std::vector<std::string> positional_;
  std::set<std::string> flags_;
  std::map<std::string, std::string> values_;
};

// Bad input found before any work starts (a bench may run for minutes before it reaches its last part).
inline void requireFile(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) throw InputError("no part file '" + path + "'");
}

// Bad input unless `name` is one of `names`, the parts a bench knows (an array or vector of names).
template <class Names>
void requireOneOf(const std::string& name, const Names& names) {
  std::string list;
  for (const auto& known : names) {
    if (name == known) return;
    list += (list.empty() ? "" : ", ") + std::string(known);
  }
  throw InputError("'" + name + "' is not one of this bench's parts: " + list);
}

// main() of a bench: `run` gets the arguments after the program's name and returns the exit code; runBench answers
// --help and turns what `run` throws into the exit codes of the rule above. `usage` starts with the bench's name.
inline int runBench(int argc, char** argv, const char* usage,
                    const std::function<int(const std::vector<std::string>&)>& run) {
  const std::vector<std::string> args(argv + std::min(argc, 1), argv + argc);
  const std::string name = argc > 0 ? std::filesystem::path(argv[0]).filename().string() : "bench";
  for (const std::string& a : args)
    if (a == "--help" || a == "-h") {
      std::printf("usage: %s", usage);
      return 0;
    }
  try {
    return run(args);
  } catch (const BenchUsageError& e) {
    std::fprintf(stderr, "%s: %s\nusage: %s", name.c_str(), e.what(), usage);
    return 2;
  } catch (const std::exception& e) {  // InputError and the rest, on one line
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    std::fprintf(stderr, "%s: %s\n", name.c_str(), what.c_str());
    return 1;
  } catch (...) {
    std::fprintf(stderr, "%s: unknown error\n", name.c_str());
    return 1;
  }
}

}  // namespace art2part
