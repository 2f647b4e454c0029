// A small command-line reader: positional arguments, --flag and --option VALUE. The art2part command and the benches
// (bench/bench_main.h) both read their arguments with it.
#pragma once

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace art2part {

// A mistake in how the command was called; main() prints it with the usage and exits 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// `text` as a finite number, all of it (std::atof would take "1mm" for 1 and garbage for 0), or a UsageError naming
// `what`: "WHAT needs a number, not 'TEXT'".
double parseNumber(const std::string& text, const std::string& what);
// `text` as a whole number written as one (no "2.5", "4.0" or "1e3") that fits an int, or a UsageError naming `what`:
// "WHAT needs a whole number, not 'TEXT'".
int parseInteger(const std::string& text, const std::string& what);

class Arguments {
 public:
  // `flags` take no value, `options` take one. Anything else starting with "--" is a UsageError; "--" alone is a
  // positional argument.
  Arguments(const std::vector<std::string>& args, const std::set<std::string>& flags,
            const std::set<std::string>& options);

  const std::vector<std::string>& positional() const { return positional_; }
  bool flag(const std::string& name) const { return flags_.count(name) > 0; }
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string value(const std::string& name, const std::string& fallback = "") const;
  // --name's value by parseNumber / parseInteger (the mistake names "--name"), or `fallback` when it is not given.
  double number(const std::string& name, double fallback) const;
  int integer(const std::string& name, int fallback) const;
  // The single positional argument a command requires, named for the error message.
  std::string requirePositional(std::size_t count, const std::string& names) const;

 private:
  std::vector<std::string> positional_;
  std::set<std::string> flags_;
  std::map<std::string, std::string> values_;
};

}  // namespace art2part
