// The benches' common command line. Each bench/*.cpp is its own executable, so this is a header (a .cpp here would
// be built as one more bench). The arguments are read by the art2part command's reader (src/cli/arguments.h:
// Arguments, parseNumber, parseInteger, UsageError), which every bench links. The rule for every bench:
//   --help or -h      the usage on stdout, exit 0
//   a usage mistake   (an unknown --option, a missing or ill-formed value, an argument too many): the mistake and
//                     the usage on stderr, exit 2
//   bad input         (a part that is not there or does not load, any other error): one line "bench_x: what" on
//                     stderr, exit 1
// Nothing escapes main: no abort. Each bench checks its arguments (and that its part files are there) before any
// work starts, so a mistake costs no minutes.
#pragma once

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "../src/cli/arguments.h"
#include "art2part/geometry/mesh.h"  // InputError

namespace art2part {

// The positional arguments, at most `most` of them: one more is a usage mistake, "unexpected argument 'X'".
inline const std::vector<std::string>& positionalAtMost(const Arguments& a, std::size_t most) {
  const std::vector<std::string>& positional = a.positional();
  if (positional.size() > most) throw UsageError("unexpected argument '" + positional[most] + "'");
  return positional;
}

// `value` if it is at least `least`, else a usage mistake naming `what`.
inline int atLeast(int value, int least, const std::string& what) {
  if (value < least) throw UsageError(what + " must be at least " + std::to_string(least));
  return value;
}

// `value` if it is above 0, else a usage mistake naming `what`.
inline double positive(double value, const std::string& what) {
  if (!(value > 0)) throw UsageError(what + " must be positive");
  return value;
}

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
  } catch (const UsageError& e) {
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
