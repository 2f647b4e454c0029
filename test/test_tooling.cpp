// Tools with real shapes, the shop's tool library, and the tools.json / toolpaths.csv file contracts.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "art2part/roughing/engagement_clearing.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {
namespace {

const std::string kLibrary = std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml";

// A file in a folder of this test's own, removed at the end.
class TempFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("art2part_tooling_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string file(const std::string& name, const std::string& text = "") const {
    const std::string path = (dir_ / name).string();
    if (!text.empty()) std::ofstream(path) << text;
    return path;
  }
  std::filesystem::path dir_;
};

// The message of the InputError that `run` throws ("" when it throws none).
template <typename Run>
std::string inputError(Run run) {
  try {
    run();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

Tool makeTool(ToolType type, double diameter, double corner) {
  Tool tool;
  tool.id = "t";
  tool.type = type;
  tool.diameter = diameter;
  tool.corner_radius = corner;
  tool.flute_length = 3 * diameter;
  tool.shank_diameter = diameter;
  tool.stickout = 5 * diameter;
  tool.holder = {{32, 20}, {40, 44}, {63, 16}};
  return tool;
}

// ---- the shop's library ---------------------------------------------------------------------------------------------

TEST(ToolLibrary, HoldsTheShopSet) {
  const ToolLibrary library = loadToolLibrary(kLibrary);
  for (const char* id : {"flat1", "flat2", "flat3", "flat4", "flat6", "flat8", "flat10", "flat12", "flat16", "flat20",
                         "ball1", "ball2", "ball3", "ball4", "ball6", "ball8", "ball10", "ball12", "bull6r0.5",
                         "bull10r1", "bull12r2", "bull16r2", "drill2.5", "drill3.3", "drill4.2", "drill5", "drill6.8",
                         "drill8.5", "drill10.2", "drill3", "drill4", "drill6", "drill8", "drill10", "drill12"})
    EXPECT_NE(library.find(id), nullptr) << id;
  EXPECT_EQ(library.find("flat7"), nullptr);
  const Tool* bull = library.find("bull10r1");
  ASSERT_NE(bull, nullptr);
  EXPECT_EQ(bull->type, ToolType::Bull);
  EXPECT_DOUBLE_EQ(bull->diameter, 10);
  EXPECT_DOUBLE_EQ(bull->corner_radius, 1);
  EXPECT_DOUBLE_EQ(library.find("ball6")->corner_radius, 3);
}

TEST(ToolLibrary, EveryToolIsValidAndRealistic) {
  for (const Tool& tool : loadToolLibrary(kLibrary).tools) {
    SCOPED_TRACE(tool.id);
    EXPECT_NO_THROW(checkTool(tool));
    EXPECT_GE(tool.flute_length, 1.5 * tool.diameter);
    // 3 x D stub drills: 20 mm flutes at 3 mm; DIN 338 jobbers: 20 mm at 1.6 mm (12.5 x D)
    EXPECT_LE(tool.flute_length, (tool.type == ToolType::Drill ? 13 : 7) * tool.diameter);
    EXPECT_GT(tool.stickout, tool.flute_length);
    EXPECT_FALSE(tool.holder.empty());
    EXPECT_LE(tool.spindle_rpm, 24000);
    EXPECT_GE(tool.feed_mm_min, tool.plunge_mm_min);
    EXPECT_LE(tool.max_stepdown, 3 * tool.diameter + 1e-9);
    EXPECT_GT(toolLength(tool), tool.stickout + 50);  // a holder a machinist would recognise
  }
}

// The high-efficiency roughing cutters: the band each lists (max_stepover) is the one constant-engagement clearing
// takes at its engagement limit on turns of two tool radii (engagement_clearing.h), its step-down within the flutes,
// its feed the stub mill's of its size with radial chip thinning at the limit (sin 78.5 deg / sin 60 deg = 1.13).
TEST(ToolLibrary, EngagementCuttersAgreeWithThePlannersBand) {
  const ToolLibrary library = loadToolLibrary(kLibrary);
  int cutters = 0;
  for (const Tool& tool : library.tools) {
    if (tool.max_engagement_deg == 0) continue;
    SCOPED_TRACE(tool.id);
    ++cutters;
    const double r = tool.diameter / 2;
    EXPECT_NEAR(tool.max_stepover, engagementStepover(r, 2 * r, tool.max_engagement_deg), 0.01);
    EXPECT_LE(tool.max_stepdown, tool.flute_length - 2 + 1e-9);
    char stub_id[32];
    std::snprintf(stub_id, sizeof stub_id, "flat%g", tool.diameter);
    const Tool* stub = library.find(stub_id);
    ASSERT_NE(stub, nullptr);
    EXPECT_NEAR(tool.feed_mm_min / stub->feed_mm_min, 0.9798 / 0.8660, 0.01);
  }
  EXPECT_GE(cutters, 4);
}

// ---- the drill cabinet (drill_series) -------------------------------------------------------------------------------

int countIds(const ToolLibrary& library, const std::string& prefix, ToolType type) {
  int count = 0;
  for (const Tool& tool : library.tools)
    if (tool.type == type && tool.id.rfind(prefix, 0) == 0) ++count;
  return count;
}

TEST(DrillSeries, HoldsTheMetricSeriesTapAndClearanceAndInchSizes) {
  const ToolLibrary library = loadToolLibrary(kLibrary);
  // 3.0 .. 14.0 by 0.1: 111 sizes per family, each id the prefix and the size's shortest decimal form.
  for (const char* prefix : {"hss", "carb"}) {
    for (int tenth = 30; tenth <= 140; ++tenth) {
      const double d = tenth / 10.0;
      char id[32];
      std::snprintf(id, sizeof id, tenth % 10 ? "%s%.1f" : "%s%.0f", prefix, d);
      const Tool* tool = library.find(id);
      ASSERT_NE(tool, nullptr) << id;
      EXPECT_EQ(tool->type, ToolType::Drill);
      EXPECT_NEAR(tool->diameter, d, 1e-12) << id;
      EXPECT_DOUBLE_EQ(tool->point_angle_deg, std::string(prefix) == "hss" ? 118 : 140) << id;
    }
  }
  // ISO 273 clearances and tap drills beyond the series, inch fractions 1/16 .. 1/2 by 1/64, letters, numbers.
  for (const char* id : {"hss1.6", "hss2.05", "hss2.2", "hss2.5", "hss2.9", "hss14.5", "carb14.5", "hss_1_16in",
                         "hss_5_64in", "hss_1_4in", "hss_31_64in", "hss_1_2in", "hss_A", "hss_H", "hss_Z", "hss_no7",
                         "hss_no50"})
    EXPECT_NE(library.find(id), nullptr) << id;
  EXPECT_EQ(countIds(library, "hss_", ToolType::Drill), 29 + 26 + 17);
  // Past 14 mm, HSS in 0.25 mm steps to 20 mm (DIN 338's straight shanks): 14.25 .. 20, 24 sizes.
  for (const char* id : {"hss14.25", "hss16", "hss19.75", "hss20"}) EXPECT_NE(library.find(id), nullptr) << id;
  EXPECT_EQ(library.find("hss20.25"), nullptr);
  EXPECT_DOUBLE_EQ(library.find("hss20")->flute_length, 140);
  EXPECT_DOUBLE_EQ(library.find("hss20")->holder.front().diameter, 50);  // ER32 for 16 .. 20 mm shanks
  EXPECT_NEAR(library.find("hss_H")->diameter, 0.266 * 25.4, 1e-9);
  EXPECT_NEAR(library.find("hss_17_64in")->diameter, 17 * 25.4 / 64, 1e-9);
  // The stubs that were there keep their ids and data (plans and tests name them).
  const Tool* stub = library.find("drill8");
  ASSERT_NE(stub, nullptr);
  EXPECT_DOUBLE_EQ(stub->flute_length, 41);
  EXPECT_DOUBLE_EQ(stub->point_angle_deg, 140);
  EXPECT_NE(library.find("spot6"), nullptr);
  EXPECT_DOUBLE_EQ(library.find("spot6")->point_angle_deg, 90);
}

// DIN 338 N and DIN 6537 L lengths, holders by shank, and cutting data from Vc and the feed per rev.
TEST(DrillSeries, GeometryAndCuttingDataFollowTheirRules) {
  const ToolLibrary library = loadToolLibrary(kLibrary);
  const Tool& hss = *library.find("hss8.4");
  EXPECT_DOUBLE_EQ(hss.flute_length, 75);      // DIN 338: 7.6 .. 8.5 mm, 75 / 117
  EXPECT_DOUBLE_EQ(hss.shank_diameter, 8.4);
  EXPECT_DOUBLE_EQ(hss.stickout, 80);          // flutes + 5 mm of shank
  EXPECT_EQ(hss.material, "hss");
  EXPECT_DOUBLE_EQ(hss.holder.front().diameter, 32);  // ER16 takes shanks to 10 mm
  EXPECT_DOUBLE_EQ(library.find("hss10.1")->holder.front().diameter, 42);  // ER25 above
  EXPECT_DOUBLE_EQ(library.find("hss8.5")->flute_length, 75);
  EXPECT_DOUBLE_EQ(library.find("hss8.6")->flute_length, 81);
  EXPECT_DOUBLE_EQ(library.find("hss2.05")->flute_length, 24);
  // rpm = 1000 Vc / (pi D) to 10 rpm; feed = rpm x 0.02 D mm/rev; peck 1.5 D.
  EXPECT_DOUBLE_EQ(hss.spindle_rpm, std::round(75000 / (M_PI * 8.4) / 10) * 10);
  EXPECT_DOUBLE_EQ(hss.feed_mm_min, std::round(hss.spindle_rpm * 0.02 * 8.4));
  EXPECT_DOUBLE_EQ(hss.plunge_mm_min, hss.feed_mm_min);
  EXPECT_DOUBLE_EQ(hss.max_stepdown, 12.6);
  const Tool& carb = *library.find("carb8.4");
  EXPECT_DOUBLE_EQ(carb.flute_length, 61);     // DIN 6537 L: 8 .. 10 mm, 61 / 103, shank 10
  EXPECT_DOUBLE_EQ(carb.shank_diameter, 10);
  EXPECT_DOUBLE_EQ(carb.spindle_rpm, std::round(150000 / (M_PI * 8.4) / 10) * 10);
  EXPECT_DOUBLE_EQ(carb.feed_mm_min, std::round(carb.spindle_rpm * 0.025 * 8.4));
  EXPECT_DOUBLE_EQ(library.find("carb3")->shank_diameter, 6);
  EXPECT_DOUBLE_EQ(library.find("carb3")->spindle_rpm, 15920);
  // 1.6 mm at 75 m/min: 14920 rpm, under the spindle's 24000; f = 0.032 mm/rev.
  EXPECT_DOUBLE_EQ(library.find("hss1.6")->spindle_rpm, 14920);
  EXPECT_DOUBLE_EQ(library.find("hss1.6")->feed_mm_min, std::round(14920 * 0.032));
}

using DrillSeriesYaml = TempFiles;

TEST_F(DrillSeriesYaml, MistakesNameTheSeriesAndTheField) {
  const std::string head = std::string("holders:\n  er16: [[32, 20], [40, 44], [63, 16]]\ntools:\n") +
                           "  - {id: flat6, type: flat, diameter: 6, flute_length: 16, stickout: 28, holder: er16}\n"
                           "drill_rules:\n"
                           "  jobber:\n"
                           "    {material: hss, point_angle_deg: 118, lengths: [[5, 52, 86], [10, 87, 133]], "
                           "visible_shank: 5, min_grip: 15, holders: [[10, er16]], vc_m_min: 75, max_rpm: 24000, "
                           "feed_per_rev: [0.02, 0.03, 0.3], peck: 1.5}\n"
                           "drill_series:\n";
  const auto load = [&](const std::string& series) {
    const std::string path = file("tools.yaml", head + series);
    return inputError([&] { loadToolLibrary(path); });
  };
  EXPECT_EQ(load("  - {rule: jobber, prefix: j, mm: {from: 3, to: 4, step: 0.5}}\n"), "");
  {
    const std::string path = file("ok.yaml", head + "  - {rule: jobber, prefix: j, mm: {from: 3, to: 4, step: 0.5}}\n");
    const ToolLibrary library = loadToolLibrary(path);
    ASSERT_EQ(library.tools.size(), 4u);
    EXPECT_EQ(library.tools[1].id, "j3");
    EXPECT_EQ(library.tools[2].id, "j3.5");
    EXPECT_EQ(library.tools[3].id, "j4");
  }
  std::string message = load("  - {rule: nosuch, prefix: j, mm: [3]}\n");
  EXPECT_TRUE(contains(message, "drill series 1") && contains(message, "nosuch")) << message;
  message = load("  - {rule: jobber, prefix: j, mm: [12]}\n");
  EXPECT_TRUE(contains(message, "12") && contains(message, "lengths")) << message;
  message = load("  - {rule: jobber, prefix: j, mm: {from: 4, to: 3, step: 0.1}}\n");
  EXPECT_TRUE(contains(message, "'to' below 'from'")) << message;
  message = load("  - {rule: jobber, prefix: j, mm: [3], inch: {H: 0.266}}\n");
  EXPECT_TRUE(contains(message, "exactly one")) << message;
  message = load("  - {rule: jobber, prefix: j, mm: [3, 3]}\n");
  EXPECT_TRUE(contains(message, "duplicate") && contains(message, "j3")) << message;
  message = load("  - {rule: jobber, prefix: j, mm: [3], colour: red}\n");
  EXPECT_TRUE(contains(message, "colour")) << message;
  message = load("  - {rule: jobber, prefix: flat, mm: [6]}\n");
  EXPECT_TRUE(contains(message, "duplicate tool id 'flat6'")) << message;
}

// The outline has no hole and no step down inside the flutes, and the holder at its face covers the shank.
TEST(ToolLibrary, OutlinesAreContinuous) {
  for (const Tool& tool : loadToolLibrary(kLibrary).tools) {
    SCOPED_TRACE(tool.id);
    const double radius = 0.5 * tool.diameter, length = toolLength(tool);
    EXPECT_EQ(toolRadiusAt(tool, -1e-9), 0);
    EXPECT_EQ(toolRadiusAt(tool, length + 1e-9), 0);
    double previous = 0;
    for (double h = 1e-6; h <= tool.flute_length; h += 0.01) {
      const double r = toolRadiusAt(tool, h);
      EXPECT_GE(r, previous - 1e-12) << "at h = " << h;
      EXPECT_LE(r, radius + 1e-12);
      previous = r;
    }
    EXPECT_DOUBLE_EQ(toolRadiusAt(tool, tool.flute_length), radius);
    for (double h = 1e-6; h < length; h += 0.05) EXPECT_GT(toolRadiusAt(tool, h), 0) << "hole at h = " << h;
    EXPECT_GE(toolRadiusAt(tool, tool.stickout + 1e-6), toolRadiusAt(tool, tool.stickout - 1e-6));
    EXPECT_GE(holderTopRadius(tool), 0.5 * tool.holder.front().diameter);
  }
}

// ---- outlines -------------------------------------------------------------------------------------------------------

TEST(ToolOutline, MatchesTheAnalyticProfiles) {
  const Tool flat = makeTool(ToolType::Flat, 10, 0);
  const Tool ball = makeTool(ToolType::Ball, 6, 3);
  const Tool bull = makeTool(ToolType::Bull, 10, 1);
  Tool drill = makeTool(ToolType::Drill, 6.8, 0);
  drill.point_angle_deg = 118;
  const double cone = std::tan(59 * M_PI / 180);
  for (double h : {0.0, 1e-4, 0.1, 0.5, 0.99, 1.0, 1.5, 2.0, 2.5, 2.999, 3.0, 4.0, 10.0}) {
    SCOPED_TRACE(h);
    EXPECT_NEAR(toolRadiusAt(flat, h), 5, 1e-9);
    EXPECT_NEAR(toolRadiusAt(ball, h), h < 3 ? std::sqrt(9 - (3 - h) * (3 - h)) : 3, 1e-9);
    EXPECT_NEAR(toolRadiusAt(bull, h), h < 1 ? 4 + std::sqrt(1 - (1 - h) * (1 - h)) : 5, 1e-9);
    EXPECT_NEAR(toolRadiusAt(drill, h), std::min(3.4, h * cone), 1e-9);
  }
  EXPECT_NEAR(toolRadiusAt(ball, 0), 0, 1e-12);
  EXPECT_NEAR(toolRadiusAt(bull, 0), 4, 1e-12);
}

TEST(ToolOutline, ShankAndHolderSteps) {
  Tool tool = makeTool(ToolType::Flat, 2, 0);  // flutes 6, stickout 10
  tool.shank_diameter = 3;
  EXPECT_DOUBLE_EQ(toolRadiusAt(tool, 6), 1);
  EXPECT_DOUBLE_EQ(toolRadiusAt(tool, 6.001), 1.5);
  EXPECT_DOUBLE_EQ(toolRadiusAt(tool, 10), 1.5);
  EXPECT_DOUBLE_EQ(toolRadiusAt(tool, 10.001), 16);
  EXPECT_DOUBLE_EQ(toolRadiusAt(tool, 30), 16);
  EXPECT_DOUBLE_EQ(toolRadiusAt(tool, 30.001), 20);
  EXPECT_DOUBLE_EQ(toolRadiusAt(tool, 74), 20);
  EXPECT_DOUBLE_EQ(toolRadiusAt(tool, 89.999), 31.5);
  EXPECT_DOUBLE_EQ(toolLength(tool), 90);
  EXPECT_DOUBLE_EQ(holderTopRadius(tool), 31.5);
  EXPECT_EQ(toolZoneAt(tool, 0), ToolZone::Flutes);
  EXPECT_EQ(toolZoneAt(tool, 6), ToolZone::Flutes);
  EXPECT_EQ(toolZoneAt(tool, 7), ToolZone::Shank);
  EXPECT_EQ(toolZoneAt(tool, 11), ToolZone::Holder);
  EXPECT_EQ(toolZoneAt(tool, 90.5), ToolZone::Above);
}

TEST(ToolCheck, NamesToolAndField) {
  const auto failure = [](Tool tool) { return inputError([&] { checkTool(tool); }); };
  EXPECT_EQ(failure(makeTool(ToolType::Bull, 10, 1)), "");
  Tool tool = makeTool(ToolType::Flat, -4, 0);
  tool.id = "flat4";
  EXPECT_TRUE(contains(failure(tool), "'flat4'") && contains(failure(tool), "diameter")) << failure(tool);
  tool = makeTool(ToolType::Bull, 10, 6);
  EXPECT_TRUE(contains(failure(tool), "corner_radius")) << failure(tool);
  tool = makeTool(ToolType::Ball, 10, 2);
  EXPECT_TRUE(contains(failure(tool), "corner_radius")) << failure(tool);
  tool = makeTool(ToolType::Flat, 10, 0);
  tool.stickout = 20;
  EXPECT_TRUE(contains(failure(tool), "stickout")) << failure(tool);
  tool = makeTool(ToolType::Flat, 10, 0);
  tool.holder.front().diameter = 8;
  EXPECT_TRUE(contains(failure(tool), "holder")) << failure(tool);
  tool = makeTool(ToolType::Ball, 10, 5);
  tool.max_engagement_deg = 60;
  EXPECT_TRUE(contains(failure(tool), "max_engagement_deg")) << failure(tool);
  tool = makeTool(ToolType::Flat, 10, 0);
  tool.max_engagement_deg = 200;
  EXPECT_TRUE(contains(failure(tool), "max_engagement_deg")) << failure(tool);
  tool = makeTool(ToolType::Drill, 10, 0);
  tool.point_angle_deg = 180;
  EXPECT_TRUE(contains(failure(tool), "point_angle_deg")) << failure(tool);
  tool = makeTool(ToolType::Flat, 10, 0);
  tool.flute_length = std::nan("");
  EXPECT_TRUE(contains(failure(tool), "flute_length")) << failure(tool);
  tool = makeTool(ToolType::Flat, 10, 0);
  tool.id = "a,b";
  EXPECT_TRUE(contains(failure(tool), "id")) << failure(tool);
  EXPECT_THROW(parseToolType("taper"), InputError);
}

// ---- config YAML with mistakes --------------------------------------------------------------------------------------

using ToolYaml = TempFiles;

const char* kHolders = "holders:\n  er16: [[32, 20], [40, 44], [63, 16]]\ntools:\n";

TEST_F(ToolYaml, BadEntriesNameTheTool) {
  const auto failure = [&](const std::string& entry) {
    const std::string path = file("tools.yaml", std::string(kHolders) +
                                                    "  - {id: flat6, type: flat, diameter: 6, flute_length: 16, "
                                                    "stickout: 28, holder: er16}\n" + entry);
    return inputError([&] { loadToolLibrary(path); });
  };
  EXPECT_EQ(failure(""), "");
  std::string message = failure("  - {id: flat8, type: flat, diameter: -8, flute_length: 20, stickout: 32, holder: er16}");
  EXPECT_TRUE(contains(message, "flat8") && contains(message, "diameter") && contains(message, "tools.yaml")) << message;
  message = failure("  - {id: bull10r6, type: bull, diameter: 10, corner_radius: 6, flute_length: 22, stickout: 38, "
                    "holder: er16}");
  EXPECT_TRUE(contains(message, "bull10r6") && contains(message, "corner_radius")) << message;
  message = failure("  - {id: flat8, type: flat, diamter: 8, flute_length: 20, stickout: 32, holder: er16}");
  EXPECT_TRUE(contains(message, "flat8") && contains(message, "diamter")) << message;
  message = failure("  - {id: flat8, type: flat, diameter: 8, flute_length: 20, stickout: 32, holder: er40}");
  EXPECT_TRUE(contains(message, "flat8") && contains(message, "er40")) << message;
  message = failure("  - {id: flat6, type: flat, diameter: 6, flute_length: 16, stickout: 28, holder: er16}");
  EXPECT_TRUE(contains(message, "duplicate")) << message;
  message = failure("  - {id: flat8, type: flat, diameter: eight, flute_length: 20, stickout: 32, holder: er16}");
  EXPECT_TRUE(contains(message, "flat8") && contains(message, "diameter")) << message;
  message = failure("  - {id: x, type: flat, diameter: [8, 20]");
  EXPECT_TRUE(contains(message, "tools.yaml")) << message;
  EXPECT_TRUE(contains(inputError([] { loadToolLibrary("/nonexistent/tools.yaml"); }), "/nonexistent/tools.yaml"));
}

// ---- tools.json -----------------------------------------------------------------------------------------------------

using ToolsJson = TempFiles;

void expectSameTool(const Tool& a, const Tool& b) {
  SCOPED_TRACE(a.id);
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.diameter, b.diameter);
  EXPECT_EQ(a.corner_radius, b.corner_radius);
  if (a.type == ToolType::Drill) {
    EXPECT_EQ(a.point_angle_deg, b.point_angle_deg);
  }
  EXPECT_EQ(a.flute_length, b.flute_length);
  EXPECT_EQ(a.shank_diameter, b.shank_diameter);
  EXPECT_EQ(a.stickout, b.stickout);
  EXPECT_EQ(a.max_engagement_deg, b.max_engagement_deg);
  ASSERT_EQ(a.holder.size(), b.holder.size());
  for (size_t s = 0; s < a.holder.size(); ++s) {
    EXPECT_EQ(a.holder[s].diameter, b.holder[s].diameter);
    EXPECT_EQ(a.holder[s].length, b.holder[s].length);
  }
  EXPECT_EQ(a.flutes, b.flutes);
  EXPECT_EQ(a.spindle_rpm, b.spindle_rpm);
  EXPECT_EQ(a.feed_mm_min, b.feed_mm_min);
  EXPECT_EQ(a.plunge_mm_min, b.plunge_mm_min);
  EXPECT_EQ(a.max_stepdown, b.max_stepdown);
  EXPECT_EQ(a.max_stepover, b.max_stepover);
  EXPECT_EQ(a.material, b.material);
}

TEST_F(ToolsJson, RoundTripGivesEqualTools) {
  std::vector<Tool> tools = loadToolLibrary(kLibrary).tools;
  tools.push_back(makeTool(ToolType::Bull, 7.3, 1.0 / 3));  // a number without a short decimal form
  const std::string path = file("tools.json");
  writeToolsJson(tools, path);
  const std::vector<Tool> back = readToolsJson(path);
  ASSERT_EQ(back.size(), tools.size());
  for (size_t t = 0; t < tools.size(); ++t) expectSameTool(tools[t], back[t]);
}

TEST_F(ToolsJson, HasExactlyTheContractKeys) {
  const std::string path = file("tools.json");
  writeToolsJson(loadToolLibrary(kLibrary).tools, path);
  const nlohmann::json list = nlohmann::json::parse(std::ifstream(path));
  ASSERT_TRUE(list.is_array());
  const std::set<std::string> contract = {"id",   "type", "diameter", "corner_radius", "flute_length", "shank_diameter",
                                          "stickout", "holder"};
  const std::set<std::string> extras = {"flutes",        "spindle_rpm",  "feed_mm_min", "plunge_mm_min",
                                        "max_stepdown", "max_stepover", "material", "max_engagement_deg"};
  for (const auto& tool : list) {
    SCOPED_TRACE(tool.dump());
    for (const std::string& key : contract) EXPECT_TRUE(tool.contains(key)) << key;
    for (const auto& [key, value] : tool.items())
      EXPECT_TRUE(contract.count(key) || extras.count(key) || (key == "point_angle_deg" && tool["type"] == "drill"))
          << key;
    EXPECT_TRUE(tool["id"].is_string());
    EXPECT_TRUE(std::set<std::string>({"flat", "ball", "bull", "drill"}).count(tool["type"].get<std::string>()));
    for (const char* key : {"diameter", "corner_radius", "flute_length", "shank_diameter", "stickout"})
      EXPECT_TRUE(tool[key].is_number()) << key;
    ASSERT_TRUE(tool["holder"].is_array());
    for (const auto& step : tool["holder"])
      EXPECT_TRUE(step.is_array() && step.size() == 2 && step[0].is_number() && step[1].is_number());
  }
}

TEST_F(ToolsJson, MissingFieldNamesTheTool) {
  const std::string path = file("tools.json", R"([{"id": "flat6", "type": "flat", "diameter": 6, "corner_radius": 0,
    "flute_length": 16, "shank_diameter": 6, "holder": [[32, 20]]}])");
  const std::string message = inputError([&] { readToolsJson(path); });
  EXPECT_TRUE(contains(message, "flat6") && contains(message, "stickout")) << message;
  const std::string minimal = file("minimal.json", R"([{"id": "flat6", "type": "flat", "diameter": 6,
    "corner_radius": 0, "flute_length": 16, "shank_diameter": 6, "stickout": 28, "holder": []}])");
  ASSERT_EQ(readToolsJson(minimal).size(), 1u);  // the contract's fields alone make a tool
  EXPECT_FALSE(inputError([&] { readToolsJson(file("bad.json", "[{")); }).empty());
}

// ---- toolpaths.csv --------------------------------------------------------------------------------------------------

using ToolpathsCsv = TempFiles;

Toolpath randomPath(int count) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-150, 150), unit(-1, 1);
  Toolpath path;
  for (int p = 0; p < count; ++p) {
    CutterLocation point;
    point.op = p / 10;
    point.setup = p / 30;
    point.tool = p % 2 ? "ball6" : "drill6.8";
    point.move = p % 3 ? MoveKind::Feed : MoveKind::Rapid;
    point.tip = Vec3(coordinate(random), coordinate(random), coordinate(random));
    point.axis = Vec3(unit(random), unit(random), unit(random) + 1.5).normalized();
    path.push_back(point);
  }
  return path;
}

TEST_F(ToolpathsCsv, RoundTripWithinAMicron) {
  const Toolpath path = randomPath(200);
  const std::string csv = file("toolpaths.csv");
  writeToolpathsCsv(path, csv);
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "op,setup,tool,move,x,y,z,i,j,k");
  const Toolpath back = readToolpathsCsv(csv);
  ASSERT_EQ(back.size(), path.size());
  for (size_t p = 0; p < path.size(); ++p) {
    EXPECT_EQ(back[p].op, path[p].op);
    EXPECT_EQ(back[p].setup, path[p].setup);
    EXPECT_EQ(back[p].tool, path[p].tool);
    EXPECT_EQ(back[p].move, path[p].move);
    EXPECT_LE((back[p].tip - path[p].tip).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LE((back[p].axis - path[p].axis).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_NEAR(back[p].axis.norm(), 1, 1e-12);
  }
  EXPECT_NEAR(toolpathLength(back, MoveKind::Feed), toolpathLength(path, MoveKind::Feed), 1e-3);
}

TEST_F(ToolpathsCsv, BadLinesNameFileAndLine) {
  const std::string good = "op,setup,tool,move,x,y,z,i,j,k\n0,0,flat6,rapid,0,0,10,0,0,1\n";
  const auto failure = [&](const std::string& row) {
    const std::string path = file("bad.csv", good + row + "\n");
    return inputError([&] { readToolpathsCsv(path); });
  };
  const std::string where = "bad.csv:3";
  std::string message = failure("0,0,flat6,feed,1,2,3,0,0");
  EXPECT_TRUE(contains(message, where) && contains(message, "missing column 'k'")) << message;
  message = failure("0,0,flat6,fly,1,2,3,0,0,1");
  EXPECT_TRUE(contains(message, where) && contains(message, "fly")) << message;
  message = failure("0,0,flat6,feed,1,NaN,3,0,0,1");
  EXPECT_TRUE(contains(message, where) && contains(message, "'y'")) << message;
  message = failure("0,0,flat6,feed,1,2,3,0,0,0");
  EXPECT_TRUE(contains(message, where) && contains(message, "unit")) << message;
  message = failure("0,0,flat6,feed,1,2,3,0,0,1.002");
  EXPECT_TRUE(contains(message, where) && contains(message, "unit")) << message;
  message = failure("0,0,flat6,feed,1,2,3mm,0,0,1");
  EXPECT_TRUE(contains(message, where) && contains(message, "'z'")) << message;
  message = failure("x,0,flat6,feed,1,2,3,0,0,1");
  EXPECT_TRUE(contains(message, where) && contains(message, "'op'")) << message;
  message = failure("0,0,flat6,feed,1,2,3,0,0,1,7");
  EXPECT_TRUE(contains(message, where) && contains(message, "columns")) << message;
  message = failure("0,0,flat6,feed,inf,2,3,0,0,1");
  EXPECT_TRUE(contains(message, where)) << message;
  EXPECT_EQ(failure("0,0,flat6,feed,1,2,3,0,0,1.0009"), "");  // within 1e-3: normalised
  EXPECT_DOUBLE_EQ(readToolpathsCsv(file("bad.csv")).back().axis.norm(), 1);
}

TEST_F(ToolpathsCsv, HeaderMustBeExact) {
  const std::string path = file("header.csv", "op,setup,tool,move,x,y,z,a,b,c\n0,0,flat6,rapid,0,0,10,0,0,1\n");
  const std::string message = inputError([&] { readToolpathsCsv(path); });
  EXPECT_TRUE(contains(message, "header.csv:1") && contains(message, "header")) << message;
  EXPECT_FALSE(inputError([&] { readToolpathsCsv(file("empty.csv", "")); }).empty());
  EXPECT_TRUE(readToolpathsCsv(file("only.csv", "op,setup,tool,move,x,y,z,i,j,k\r\n")).empty());
}

TEST_F(ToolpathsCsv, WriterRefusesWhatTheReaderWould) {
  Toolpath path = randomPath(3);
  path[1].tip.x() = std::nan("");
  EXPECT_THROW(writeToolpathsCsv(path, file("nan.csv")), InputError);
  path = randomPath(3);
  path[2].tool = "flat,6";
  EXPECT_THROW(writeToolpathsCsv(path, file("comma.csv")), InputError);
}

TEST(ToolpathLength, SumsMovesOfOneKind) {
  Toolpath path(4);
  path[0].tip = Vec3(0, 0, 10);
  path[1].tip = Vec3(0, 0, 0), path[1].move = MoveKind::Feed;
  path[2].tip = Vec3(3, 4, 0), path[2].move = MoveKind::Feed;
  path[3].tip = Vec3(3, 4, 10), path[3].move = MoveKind::Rapid;
  EXPECT_DOUBLE_EQ(toolpathLength(path, MoveKind::Feed), 15);
  EXPECT_DOUBLE_EQ(toolpathLength(path, MoveKind::Rapid), 10);
  EXPECT_EQ(toolpathLength({}, MoveKind::Feed), 0);
}

}  // namespace
}  // namespace art2part
