// The setup sheet (setup_sheet.h).
#include "art2part/plan/setup_sheet.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "art2part/render/annotate.h"
#include "art2part/render/palette.h"
#include "art2part/render/picture.h"

namespace art2part {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr int kSetupPictureWidth = 640, kSetupPictureHeight = 480;

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const unsigned n = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) << 8 : 0) |
                       (i + 2 < bytes.size() ? static_cast<unsigned char>(bytes[i + 2]) : 0);
    out += table[(n >> 18) & 63];
    out += table[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? table[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? table[n & 63] : '=';
  }
  return out;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

json readJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError("no setup sheet: cannot read " + path.string());
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw InputError("no setup sheet: " + path.string() + " is not JSON: " + e.what());
  }
}

// An inline picture, or nothing when the file is not there.
std::string image(const fs::path& path, const std::string& alt) {
  if (!fs::is_regular_file(path)) return "";
  return "<img alt=\"" + escape(alt) + "\" src=\"data:image/png;base64," + base64(slurp(path)) + "\">";
}

std::string fixed(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

std::string duration(double seconds) {
  const long s = std::lround(seconds);
  char text[64];
  if (s >= 3600) std::snprintf(text, sizeof text, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  else std::snprintf(text, sizeof text, "%ld min %02ld s", s / 60, s % 60);
  return text;
}

std::string vector3(const json& v) {
  if (!v.is_array() || v.size() != 3) return "";
  return "(" + fixed(v[0].get<double>(), 3) + ", " + fixed(v[1].get<double>(), 3) + ", " + fixed(v[2].get<double>(), 3) + ")";
}

std::string direction(const json& v) {
  if (!v.is_array() || v.size() != 3) return "";
  return directionLabel(Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>()));
}

std::string holderText(const json& tool) {
  std::string text;
  for (const json& step : tool.value("holder", json::array()))
    if (step.is_array() && step.size() == 2)
      text += (text.empty() ? "" : ", ") + fixed(step[0].get<double>(), 0) + "x" + fixed(step[1].get<double>(), 0);
  return text.empty() ? "-" : "&#8960;x length: " + text;
}

std::string toolRow(const json& tool) {
  std::ostringstream row;
  row << "<tr><td>" << escape(tool.value("id", "")) << "</td><td>" << escape(tool.value("type", "")) << " &#8960;"
      << fixed(tool.value("diameter", 0.0), 2) << "</td><td>" << fixed(tool.value("flute_length", 0.0), 1) << "</td><td>"
      << fixed(tool.value("stickout", 0.0), 1) << "</td><td>" << holderText(tool) << "</td><td>"
      << fixed(tool.value("spindle_rpm", 0.0), 0) << "</td><td>" << fixed(tool.value("feed_mm_min", 0.0), 0) << "</td></tr>\n";
  return row.str();
}

std::string fixtureNote(const json& setup) {
  if (setup.contains("fixture") && setup["fixture"].is_object()) {
    const json& f = setup["fixture"];
    std::string text = "Clamp the part with the setup direction " + direction(setup.value("direction", json())) +
                       " pointing up; part frame on the table at " + vector3(f.value("origin_mm", json())) + " mm";
    if (f.contains("note")) text += "; " + f["note"].get<std::string>();
    return escape(text);
  }
  return "Clamp the part with the setup direction " + escape(direction(setup.value("direction", json()))) +
         " pointing up, towards the spindle; the stock's bottom centre on the table's origin.";
}

std::string setupSection(const fs::path& dir, const json& plan, const json& setup, int k,
                         const std::map<std::string, json>& tools) {
  std::ostringstream s;
  const json& frame = setup.value("frame", json::object());
  s << "<h2>Setup " << k << ": " << escape(direction(setup.value("direction", json()))) << " up"
    << (setup.value("for_finishing", false) ? " (added for finishing)" : "") << "</h2>\n<div class=\"setup\">"
    << image(dir / ("setup_" + std::to_string(k) + ".png"), "setup " + std::to_string(k)) << "<div>\n"
    << "<p><b>Frame</b> setup_" << k << ": origin " << vector3(frame.value("origin", json())) << " mm, x "
    << vector3(frame.value("x", json())) << ", y " << vector3(frame.value("y", json())) << ", z "
    << vector3(frame.value("z", json())) << " (part frame)</p>\n<p><b>Fixture</b> " << fixtureNote(setup) << "</p>\n";
  std::vector<std::string> loaded;
  double seconds = 0;
  std::ostringstream ops;
  for (const json& op : plan.value("operations", json::array())) {
    if (op.value("setup", -1) != k) continue;
    const std::string tool = op.value("tool", "");
    if (std::find(loaded.begin(), loaded.end(), tool) == loaded.end()) loaded.push_back(tool);
    const auto t = tools.find(tool);
    const double feed = t != tools.end() ? t->second.value("feed_mm_min", 0.0) : 0.0;
    const double rpm = t != tools.end() ? t->second.value("spindle_rpm", 0.0) : 0.0;
    seconds += op.value("time_s", 0.0);
    ops << "<tr><td>" << op.value("index", 0) << "</td><td>" << escape(op.value("stage", "")) << "</td><td>"
        << escape(op.value("kind", "")) << "</td><td>" << escape(tool) << "</td><td>" << fixed(rpm, 0) << "</td><td>"
        << fixed(feed, 0) << "</td><td>" << fixed(op.value("length_mm", 0.0) / 1000, 2) << "</td><td>"
        << duration(op.value("time_s", 0.0)) << "</td></tr>\n";
  }
  s << "<p><b>Tools</b> (" << loaded.size() << " loads, mm)</p>\n<table><tr><th>tool</th><th>type</th><th>flutes</th>"
    << "<th>stickout</th><th>holder</th><th>rpm</th><th>feed mm/min</th></tr>\n";
  for (const std::string& id : loaded) {
    const auto t = tools.find(id);
    if (t != tools.end()) s << toolRow(t->second);
  }
  s << "</table>\n<p><b>Operations</b> in order, estimated " << duration(seconds) << "</p>\n"
    << "<table><tr><th>#</th><th>stage</th><th>strategy</th><th>tool</th><th>rpm</th><th>feed mm/min</th>"
    << "<th>cutting m</th><th>time</th></tr>\n"
    << ops.str() << "</table>\n</div></div>\n";
  return s.str();
}

}  // namespace

void writeSetupPictures(const std::string& dir, const Part& part, const SetupPlan& setups) {
  for (int k = 0; k < static_cast<int>(setups.setups.size()); ++k) {
    const Setup& setup = setups.setups[k];
    PictureOptions picture;
    picture.width = kSetupPictureWidth;
    picture.height = kSetupPictureHeight;
    // Along the direction, a little from the side so that walls show.
    picture.view_direction = setup.frame.z.normalized() * 3 + setup.frame.x * 0.6 - setup.frame.y * 0.9;
    picture.triangle_colours.assign(part.mesh.triangleCount(), {205, 205, 205});
    const Rgb c = setupColour(k);
    for (int t : setup.triangles)
      picture.triangle_colours[t] = {static_cast<unsigned char>(255 * c[0]), static_cast<unsigned char>(255 * c[1]),
                                     static_cast<unsigned char>(255 * c[2])};
    const std::string title = "setup " + std::to_string(k) + ": " + directionLabel(setup.frame.z) + " up";
    const Image image = withLegend(renderPicture(part.mesh, picture), title,
                                   {{c, "machined in this setup"}, {Rgb{0.8f, 0.8f, 0.8f}, "other setups"}});
    const std::string path = (fs::path(dir) / ("setup_" + std::to_string(k) + ".png")).string();
    try {
      writePng(image, path);
    } catch (const std::runtime_error& e) {
      throw InputError(e.what());
    }
  }
}

std::string setupSheetHtml(const std::string& dir_name) {
  const fs::path dir(dir_name);
  const json plan = readJson(dir / "plan.json");
  std::map<std::string, json> tools;
  for (const json& t : readJson(dir / "tools.json")) tools[t.value("id", "")] = t;
  const json& part = plan.value("part", json::object());
  const std::string name = fs::path(part.value("source", std::string("part"))).filename().string();
  const json& time = plan.value("machining_time", json::object());
  const json& finishing = plan.value("finishing", json::object());
  const json& program = plan.value("program", json::object());
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Setup sheet: " << escape(name) << "</title>\n"
    << "<style>body{font-family:sans-serif;margin:2em;max-width:1400px}table{border-collapse:collapse;margin:0.5em 0}"
    << "td,th{border:1px solid #bbb;padding:2px 8px;text-align:left}th{background:#eee}.setup{display:flex;gap:1.5em;"
    << "align-items:flex-start}img{max-width:100%;border:1px solid #ccc}</style></head><body>\n"
    << "<h1>Setup sheet: " << escape(name) << "</h1>\n<table>"
    << "<tr><th>machine</th><td>" << escape(program.value("machine", "")) << "</td></tr>"
    << "<tr><th>program</th><td>"
    << (program.value("written", false) ? "program.ngc (setup_&lt;k&gt;.ngc per setup)"
                                        : "none: " + escape(program.value("error", "")))
    << "</td></tr><tr><th>setups</th><td>" << plan.value("setups", json::array()).size() << " (" << escape(plan.value("mode", ""))
    << ")</td></tr><tr><th>operations</th><td>" << plan.value("operations", json::array()).size() << "</td></tr>"
    << "<tr><th>machining time</th><td>" << duration(time.value("total_s", 0.0)) << " (roughing "
    << duration(time.value("roughing_s", 0.0)) << ", finishing " << duration(time.value("finishing_s", 0.0))
    << ", setup changes " << duration(time.value("setup_change_s", 0.0)) << "; cutting "
    << duration(time.value("cutting_s", 0.0)) << ", rapids " << duration(time.value("rapid_s", 0.0))
    << ")</td></tr><tr><th>tool changes</th><td>" << time.value("tool_changes", 0) << " ("
    << finishing.value("tool_changes", 0) << " in finishing)</td></tr></table>\n";
  const json& setups = plan.value("setups", json::array());
  for (int k = 0; k < static_cast<int>(setups.size()); ++k) h << setupSection(dir, plan, setups[k], k, tools);
  h << "<h2>Verification (simulation of every operation in order)</h2>\n";
  const json& v = plan.value("verification", json());
  if (v.is_object()) {
    h << "<table><tr><th>gouges</th><td>" << v.value("gouges", 0) << "</td></tr><tr><th>collisions</th><td>"
      << v.value("collisions", 0) << " (shank, holder, rapids through stock)</td></tr><tr><th>result</th><td>"
      << (v.value("passed", false) ? "passed: nothing gouges or collides" : "FAILED") << "; "
      << escape(v.value("what_is_left", "")) << "</td></tr><tr><th>lattice</th><td>"
      << fixed(v.value("resolution_mm", 0.0), 2) << " mm</td></tr></table>\n";
  } else {
    h << "<p>Not simulated.</p>\n";
  }
  h << "<div class=\"setup\">" << image(dir / "setups.png", "setups") << image(dir / "remaining.png", "what is left")
    << "</div>\n";
  const json& by = finishing.value("faces_by_status", json::object());
  if (!by.empty()) {
    h << "<p><b>Faces</b>: ";
    for (const auto& [status, count] : by.items()) h << escape(status) << " " << count.get<int>() << "; ";
    h << "plan.json's faces says why for each.</p>\n";
  }
  h << "</body></html>\n";
  return h.str();
}

void writeSetupSheet(const std::string& dir) {
  const std::string html = setupSheetHtml(dir);
  const fs::path path = fs::path(dir) / "setup_sheet.html";
  std::ofstream out(path);
  if (!out) throw InputError("cannot write '" + path.string() + "'");
  out << html;
  if (!out) throw InputError("cannot write '" + path.string() + "'");
}

}  // namespace art2part
