// The plan folder (plan_folder.h): what writePlanFolder writes is what readPlanFolder reads back (the path point for
// point, the tools, plan.json); the setup sheet is self-contained and names every setup and operation; a folder
// without its files is refused naming the file. Pictures carry a title and a legend (annotate.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "art2part/kinematics/machine.h"
#include "art2part/plan/plan_folder.h"
#include "art2part/render/annotate.h"
#include "art2part/tooling/tool.h"
#include "test_meshes.h"
#include "test_solids.h"

namespace art2part {
namespace {

namespace fs = std::filesystem;

const std::string kConfig = std::string(ART2PART_SOURCE_DIR) + "/config";

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(PlanFolder, WritesTheContractAndReadsItBack) {
  const Part part = test::stepPart(test::pocketedBlock(Vec3(0, 0, 0), Vec3(60, 40, 20), 30, 20, 8, 4), "pocket");
  const ToolLibrary library = loadToolLibrary(kConfig + "/tools.yaml");
  PlanOptions options;
  options.visibility.level = 2;
  const PlanResult plan = planPart(part, library, options);
  ASSERT_FALSE(plan.toolpath.empty());
  PlanFolderOptions folder;
  folder.program.machine = loadMachine(kConfig + "/machines/vmc_3axis.yaml");
  folder.program.clampings = setupClampings(folder.program.machine, part, plan.setups, options.roughing);
  const std::string dir = test::tempDir() + "/plan";
  const WrittenPlan written = writePlanFolder(dir, part, plan, folder, {{"load", 0.5}});
  EXPECT_TRUE(written.program_written) << written.program_error;
  for (const char* file : {"plan.json", "toolpaths.csv", "tools.json", "mesh.stl", "directions.csv", "visibility.bits",
                           "setups.png", "remaining.png", "program.ngc", "setup_sheet.html"})
    EXPECT_TRUE(fs::is_regular_file(fs::path(dir) / file)) << file;
  EXPECT_EQ(written.plan["timings"]["load"], 0.5);

  const PlanFolder back = readPlanFolder(dir);
  ASSERT_EQ(back.toolpath.size(), plan.toolpath.size());
  for (std::size_t i = 0; i < plan.toolpath.size(); i += 97) {
    EXPECT_LT((back.toolpath[i].tip - plan.toolpath[i].tip).norm(), 1e-3) << i;
    EXPECT_EQ(back.toolpath[i].tool, plan.toolpath[i].tool) << i;
    EXPECT_EQ(back.toolpath[i].op, plan.toolpath[i].op) << i;
  }
  ASSERT_EQ(back.tools.size(), plan.tools.size());
  for (std::size_t i = 0; i < plan.tools.size(); ++i) EXPECT_EQ(back.tools[i].id, plan.tools[i].id);
  EXPECT_EQ(back.plan["operations"].size(), plan.operations.size());
  EXPECT_FALSE(back.mesh_path.empty());

  const nlohmann::json summary = planSummary(back.plan);
  EXPECT_EQ(summary["operations"], plan.operations.size());
  EXPECT_EQ(summary["setups"], plan.setups.setups.size());

  // The sheet: every setup with its picture, every operation by its number, nothing fetched from elsewhere.
  const std::string html = test::slurp(fs::path(dir) / "setup_sheet.html");
  for (std::size_t k = 0; k < plan.setups.setups.size(); ++k)
    EXPECT_NE(html.find("<h2>Setup " + std::to_string(k) + ":"), std::string::npos) << "setup " << k;
  for (const PlanOperation& op : plan.operations)
    EXPECT_NE(html.find("<tr><td>" + std::to_string(op.index) + "</td>"), std::string::npos) << "operation " << op.index;
  EXPECT_GE(count(html, "src=\"data:image/png;base64,"), static_cast<int>(plan.setups.setups.size()) + 2);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href="), std::string::npos);
  EXPECT_NE(html.find(written.plan["verification"]["what_is_left"].get<std::string>()), std::string::npos);
  for (const Tool& t : plan.tools) EXPECT_NE(html.find("<td>" + t.id + "</td>"), std::string::npos) << t.id;
}

TEST(PlanFolder, RefusesAFolderWithoutItsFilesNamingTheFile) {
  const std::string dir = test::tempDir();
  try {
    readPlanFolder(dir);
    FAIL() << "an empty folder was read as a plan";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("toolpaths.csv"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readPlanFolder(dir + "/none"), InputError);
}

// A legend is a title band and a column of swatches with their labels; the text is really drawn (dark pixels where
// it goes, wider for a longer text).
TEST(Annotate, PicturesCarryATitleAndALegend) {
  Image white;
  white.width = 200;
  white.height = 150;
  white.rgb.assign(200 * 150 * 3, 255);
  const Image out = withLegend(white, "a title", {{Rgb{1, 0, 0}, "setup 0: +z"}, {Rgb{0, 0, 1}, "setup 1: -x"}});
  EXPECT_GT(out.width, white.width);
  EXPECT_GT(out.height, white.height);
  auto pixel = [&](int x, int y) { return &out.rgb[(static_cast<std::size_t>(y) * out.width + x) * 3]; };
  int dark_in_title = 0, red = 0, blue = 0;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const unsigned char* p = pixel(x, y);
      if (y < out.height - white.height && x < 200 && p[0] < 100 && p[1] < 100 && p[2] < 100) ++dark_in_title;
      if (x >= white.width && p[0] > 240 && p[1] < 20 && p[2] < 20) ++red;
      if (x >= white.width && p[2] > 240 && p[0] < 20 && p[1] < 20) ++blue;
    }
  EXPECT_GT(dark_in_title, 20) << "no title drawn (is fonts-dejavu-core installed?)";
  EXPECT_GT(red, 100);
  EXPECT_GT(blue, 100);
  Image canvas = white;
  const int short_text = drawText(canvas, 0, 0, "ab", 16, {0, 0, 0});
  const int long_text = drawText(canvas, 0, 40, "abcdefgh", 16, {0, 0, 0});
  EXPECT_GT(short_text, 0);
  EXPECT_GT(long_text, 3 * short_text);

  ColourScale scale;
  scale.caption = "stock";
  scale.unit = "mm";
  scale.high = 2;
  scale.colour = [](double v) { return rampColour(v / 2); };
  const Image bar = withScale(white, "t", scale);
  EXPECT_GT(bar.width, white.width);
  EXPECT_EQ(directionLabel(Vec3(0, 0, -2)), "-z");
  EXPECT_EQ(directionLabel(Vec3(1, 0, 1)), "(0.71, 0.00, 0.71)");
}

}  // namespace
}  // namespace art2part
