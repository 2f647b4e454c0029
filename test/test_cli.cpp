// The art2part command line as a user meets it: exit codes, one-line errors, JSON that parses.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <cstdio>
#include <filesystem>
#include <utility>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include "art2part/geometry/mesh_io.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

struct CliRun {
  int status = -1;
  std::string out, err;
};

CliRun run(const std::string& arguments) {
  const std::string dir = test::tempDir();
  const std::string command =
      std::string(ART2PART_CLI) + " " + arguments + " > " + dir + "/out 2> " + dir + "/err";
  CliRun r;
  const int raw = std::system(command.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  r.out = slurp(dir + "/out");
  r.err = slurp(dir + "/err");
  return r;
}

const std::string kExample = std::string(ART2PART_SOURCE_DIR) + "/examples/nist_ctc_01_asme1_rd.stp";

}  // namespace

TEST(Cli, InfoJsonDescribesTheExamplePart) {
  const CliRun r = run("info " + kExample + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["faces"]["total"], 139);
  EXPECT_EQ(j["faces"]["cylinder"], 57);
  EXPECT_EQ(j["faces_from"], "brep");
  EXPECT_TRUE(j["closed"].get<bool>());
  EXPECT_GT(j["volume_mm3"].get<double>(), 0.0);
  // SOURCES.md: an 800 x 450 x 150 mm plate.
  const auto size = j["bounding_box"]["size"];
  EXPECT_NEAR(size[0].get<double>(), 800.0, 1.0);
  EXPECT_NEAR(size[1].get<double>(), 450.0, 1.0);
  EXPECT_NEAR(size[2].get<double>(), 150.0, 1.0);
}

TEST(Cli, InfoTextNamesRepairsAndWarnings) {
  const std::string dir = test::tempDir();
  Mesh open = test::box(Vec3(0, 0, 0), Vec3(10, 10, 10));
  open.triangles.resize(10);
  writeBinaryStl(open, dir + "/open.stl");
  const CliRun r = run("info " + dir + "/open.stl");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("merged duplicate vertices"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("warning:    the mesh is open: 4 boundary edges"), std::string::npos) << r.out;
}

TEST(Cli, BadInputGivesOneLineAndExitOne) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/junk.stl", "not a mesh at all\n");
  for (const std::string& file : {dir + "/junk.stl", dir + "/missing.stp", dir}) {
    const CliRun r = run("info " + file);
    EXPECT_EQ(r.status, 1) << file;
    EXPECT_EQ(r.err.rfind("art2part: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty());
  }
}

TEST(Cli, VisibilityWritesTheContractFiles) {
  const std::string dir = test::tempDir() + "/vis";
  const CliRun r = run("visibility " + kExample + " --out " + dir + " --level 1 --picture " + dir + "/cones.png");
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream csv(dir + "/directions.csv");
  const int lines = static_cast<int>(std::count(std::istreambuf_iterator<char>(csv), {}, '\n'));
  EXPECT_GE(lines, 16);  // 4 * 4^1 cells, special directions replace or join them
  std::ifstream stl(dir + "/mesh.stl", std::ios::binary);
  char header[84];
  ASSERT_TRUE(stl.read(header, 84));
  std::uint32_t triangles = 0;
  std::memcpy(&triangles, header + 80, 4);
  std::ifstream bits(dir + "/visibility.bits", std::ios::binary | std::ios::ate);
  EXPECT_EQ(static_cast<long>(bits.tellg()), static_cast<long>(triangles) * ((lines + 7) / 8));
  EXPECT_TRUE(std::ifstream(dir + "/cones.png").good());
  // An output folder that cannot be made: one line, exit 1.
  const CliRun bad = run("visibility " + kExample + " --out /proc/art2part/nope --level 1");
  EXPECT_EQ(bad.status, 1) << bad.err;
  EXPECT_EQ(bad.err.rfind("art2part: error: ", 0), 0u) << bad.err;
}

TEST(Cli, MisuseGivesUsageAndExitTwo) {
  EXPECT_EQ(run("info").status, 2);
  EXPECT_EQ(run("info " + kExample + " --no-such-option").status, 2);
  EXPECT_EQ(run("info " + kExample + " --units furlongs").status, 1);
  EXPECT_EQ(run("frobnicate").status, 2);
  EXPECT_EQ(run("visibility " + kExample).status, 2) << "no --out";
  EXPECT_EQ(run("visibility " + kExample + " --out /tmp/x --level 9").status, 1) << "level out of range";
}

// A number is all of its text and finite, a whole number is written as one and fits an int: else a usage mistake that
// names the option and the text, found before the part is read (the part here is not there: exit 1 once they pass).
TEST(Cli, IllFormedNumbersAreUsageMistakes) {
  const std::string missing = test::tempDir() + "/missing.stl";
  const std::string visibility = "visibility " + missing + " --out " + test::tempDir() + "/vis";
  const std::pair<std::string, std::string> cases[] = {
      {"info " + missing + " --tolerance 1mm", "--tolerance needs a number, not '1mm'"},
      {"info " + missing + " --tolerance x", "--tolerance needs a number, not 'x'"},
      {"info " + missing + " --tolerance inf", "--tolerance needs a number, not 'inf'"},
      {visibility + " --threads 2.5", "--threads needs a whole number, not '2.5'"},
      {visibility + " --level 4.0", "--level needs a whole number, not '4.0'"},
      {visibility + " --samples 1e3", "--samples needs a whole number, not '1e3'"},
      {visibility + " --threads 99999999999", "--threads needs a whole number, not '99999999999'"},
  };
  for (const auto& [arguments, mistake] : cases) {
    const CliRun r = run(arguments);
    EXPECT_EQ(r.status, 2) << arguments << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("art2part: " + mistake + "\n", 0), 0u) << r.err;
  }
  EXPECT_EQ(run("info " + missing + " --tolerance 0.5").status, 1);
  EXPECT_EQ(run(visibility + " --threads 2 --level 1").status, 1);
}

// A machine whose travel the part exceeds: the plan is written, the program is not, and the output says so (the
// wrote line once listed program.ngc all the same: CTC-02 on the default VMC).
TEST(Cli, PlanOnAMachineTooSmallWritesNoProgramAndSaysSo) {
  const std::string dir = test::tempDir();
  std::ifstream vmc(std::string(ART2PART_SOURCE_DIR) + "/config/machines/vmc_3axis.yaml");
  std::string yaml(std::istreambuf_iterator<char>(vmc), {});
  const std::size_t z = yaml.find("max: 1200");
  ASSERT_NE(z, std::string::npos);
  yaml.replace(z, 9, "max: 20");  // 20 mm of Z travel
  std::ofstream(dir + "/small.yaml") << yaml;
  const CliRun plan = run("plan " + std::string(ART2PART_SHARED_PARTS) + "/featuretype.STEP --out " + dir +
                          "/plan --no-finish --machine " + dir + "/small.yaml");
  EXPECT_EQ(plan.status, 0) << plan.err;
  EXPECT_NE(plan.err.find("no program for"), std::string::npos) << plan.err;
  const std::size_t wrote = plan.out.find("wrote:");
  ASSERT_NE(wrote, std::string::npos) << plan.out;
  EXPECT_EQ(plan.out.find("program.ngc", wrote), std::string::npos) << plan.out.substr(wrote);
  EXPECT_FALSE(std::filesystem::exists(dir + "/plan/program.ngc"));
  std::ifstream in(dir + "/plan/plan.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_FALSE(j["program"]["written"].get<bool>());
}

// `art2part COMMAND --help` is a request, not a mistake: that command's usage alone on stdout, exit 0, and nothing run
// (a --help among a plan's arguments must not start a plan).
TEST(Cli, CommandHelpPrintsItsUsageAndExitsZero) {
  for (const char* command : {"info", "render", "visibility", "setups", "plan", "verify", "post", "urdf"}) {
    SCOPED_TRACE(command);
    const CliRun r = run(std::string(command) + " --help");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find(std::string("usage: art2part  ") + command), std::string::npos) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;
  }
  const std::string dir = test::tempDir();
  const CliRun plan = run("plan " + kExample + " --out " + dir + "/plan --help");
  EXPECT_EQ(plan.status, 0);
  EXPECT_FALSE(std::filesystem::exists(dir + "/plan")) << "--help ran the plan";
  // Only that command: the other commands' lines are not printed.
  EXPECT_EQ(run("info --help").out.find("visibility PART"), std::string::npos);
}
