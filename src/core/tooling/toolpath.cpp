// toolpaths.csv: cutter-location points, one row each, read strictly and written with 1e-6 mm resolution.
// Numbers go through std::from_chars / std::to_chars, so the process locale cannot change the decimal point.
#include "art2part/tooling/toolpath.h"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>

namespace art2part {

namespace {

constexpr const char* kHeader = "op,setup,tool,move,x,y,z,i,j,k";
constexpr int kColumns = 10;
constexpr double kAxisTolerance = 1e-3;

const std::array<const char*, kColumns> kColumnNames = {"op", "setup", "tool", "move", "x", "y", "z", "i", "j", "k"};

std::string_view trimmed(std::string_view text) {
  const size_t first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

// Splits one line at commas; an error when it has not exactly the contract's columns.
std::array<std::string_view, kColumns> splitRow(std::string_view line, const std::string& where) {
  std::array<std::string_view, kColumns> fields;
  int count = 0;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    if (count == kColumns) throw InputError(where + ": more than " + std::to_string(kColumns) + " columns");
    fields[count++] = trimmed(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (count < kColumns)
    throw InputError(where + ": missing column '" + kColumnNames[count] + "' (" + std::to_string(count) + " of " +
                     std::to_string(kColumns) + " columns)");
  return fields;
}

int parseIndex(std::string_view text, int column, const std::string& where) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < 0)
    throw InputError(where + ": column '" + kColumnNames[column] + "' is not a non-negative integer: '" +
                     std::string(text) + "'");
  return value;
}

double parseNumber(std::string_view text, int column, const std::string& where) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size())
    throw InputError(where + ": column '" + kColumnNames[column] + "' is not a number: '" + std::string(text) + "'");
  if (!std::isfinite(value))
    throw InputError(where + ": column '" + kColumnNames[column] + "' is not finite: '" + std::string(text) + "'");
  return value;
}

MoveKind parseMove(std::string_view text, const std::string& where) {
  if (text == "rapid") return MoveKind::Rapid;
  if (text == "feed") return MoveKind::Feed;
  throw InputError(where + ": unknown move '" + std::string(text) + "' (expected rapid or feed)");
}

Vec3 parseVector(const std::array<std::string_view, kColumns>& fields, int first, const std::string& where) {
  return Vec3(parseNumber(fields[first], first, where), parseNumber(fields[first + 1], first + 1, where),
              parseNumber(fields[first + 2], first + 2, where));
}

CutterLocation parseRow(std::string_view line, const std::string& where) {
  const auto fields = splitRow(line, where);
  CutterLocation point;
  point.op = parseIndex(fields[0], 0, where);
  point.setup = parseIndex(fields[1], 1, where);
  if (fields[2].empty()) throw InputError(where + ": empty tool id");
  point.tool = std::string(fields[2]);
  point.move = parseMove(fields[3], where);
  point.tip = parseVector(fields, 4, where);
  const Vec3 axis = parseVector(fields, 7, where);
  const double norm = axis.norm();
  if (std::abs(norm - 1) > kAxisTolerance)
    throw InputError(where + ": tool axis (i,j,k) is not a unit vector: length " + std::to_string(norm) +
                     ", allowed 1 +- 0.001");
  point.axis = axis / norm;
  return point;
}

}  // namespace

CutterLocation cutterLocation(int setup, const std::string& tool, MoveKind move, const Vec3& tip, const Vec3& axis) {
  CutterLocation c;
  c.setup = setup;
  c.tool = tool;
  c.move = move;
  c.tip = tip;
  c.axis = axis;
  return c;
}

void appendFixed(std::string& out, double value, int decimals) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, decimals);
  std::string_view text(buffer, result.ptr - buffer);
  // "-0.000000" reads as an oddity in a file people look at: write it as 0.
  if (text.front() == '-' && text.find_first_not_of("-0.") == std::string_view::npos) text.remove_prefix(1);
  out += text;
}

namespace {

void appendRow(std::string& out, const CutterLocation& point) {
  out += std::to_string(point.op);
  out += ',';
  out += std::to_string(point.setup);
  out += ',';
  out += point.tool;
  out += point.move == MoveKind::Rapid ? ",rapid" : ",feed";
  for (int c = 0; c < 3; ++c) (out += ','), appendFixed(out, point.tip[c], 6);
  for (int c = 0; c < 3; ++c) (out += ','), appendFixed(out, point.axis[c], 9);
  out += '\n';
}

// What the reader would refuse, the writer refuses too.
void checkWritable(const CutterLocation& point, size_t index) {
  const std::string where = "toolpath point " + std::to_string(index);
  if (point.tool.empty() || point.tool.find_first_of(",\r\n") != std::string::npos)
    throw InputError(where + ": tool id '" + point.tool + "' is empty or holds a comma or line break");
  if (point.op < 0 || point.setup < 0) throw InputError(where + ": negative op or setup index");
  if (!point.tip.allFinite() || !point.axis.allFinite()) throw InputError(where + ": NaN or infinite coordinate");
  if (std::abs(point.axis.norm() - 1) > kAxisTolerance) throw InputError(where + ": tool axis is not a unit vector");
}

}  // namespace

Toolpath readToolpathsCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("'" + path + "': cannot open toolpaths.csv");
  std::string line;
  if (!std::getline(in, line)) throw InputError(path + ":1: empty file, expected the header " + kHeader);
  if (trimmed(line) != kHeader)
    throw InputError(path + ":1: header is '" + std::string(trimmed(line)) + "', expected '" + kHeader + "'");
  Toolpath points;
  for (int number = 2; std::getline(in, line); ++number) {
    if (trimmed(line).empty()) continue;
    points.push_back(parseRow(line, path + ":" + std::to_string(number)));
  }
  return points;
}

void writeToolpathsCsv(const Toolpath& path, const std::string& file) {
  std::string text = std::string(kHeader) + "\n";
  text.reserve(text.size() + 96 * path.size());
  for (size_t p = 0; p < path.size(); ++p) {
    checkWritable(path[p], p);
    appendRow(text, path[p]);
  }
  std::ofstream out(file, std::ios::binary);
  if (!out) throw InputError("'" + file + "': cannot open for writing");
  out << text;
  if (!out) throw InputError("'" + file + "': write failed");
}

double toolpathLength(const Toolpath& path, MoveKind kind) {
  double length = 0;
  for (size_t p = 1; p < path.size(); ++p)
    if (path[p].move == kind) length += (path[p].tip - path[p - 1].tip).norm();
  return length;
}

}  // namespace art2part
