// Path confinement (issue 18 item 7): only paths inside the configured folders pass, whatever `..`, links, prefixes
// or slashes the request uses, and a refusal reads the same whether or not the file exists.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "art2part/common/confined_path.h"
#include "test_meshes.h"

using namespace art2part;
namespace fs = std::filesystem;

namespace {

// base/
//   parts/            the root          sub/a.stl, a file; in -> sub (a link that stays inside)
//                                       out -> base/outside, rel -> ../outside (links out), dangle -> a missing file
//                                       outside, loop1 <-> loop2
//   partsx/b.stl      a sibling whose name starts with the root's
//   outside/secret.stl
//   rootlink -> parts a root named through a link
class ConfinedPathTest : public ::testing::Test {
 protected:
  void SetUp() override {
    base = fs::path(test::tempDir());
    parts = base / "parts";
    fs::create_directories(parts / "sub");
    fs::create_directories(base / "partsx");
    fs::create_directories(base / "outside");
    for (const fs::path& f : {parts / "sub" / "a.stl", base / "partsx" / "b.stl", base / "outside" / "secret.stl"})
      std::ofstream(f) << "solid x\nendsolid x\n";
    fs::create_directory_symlink(parts / "sub", parts / "in");
    fs::create_directory_symlink(base / "outside", parts / "out");
    fs::create_directory_symlink("../outside", parts / "rel");
    fs::create_symlink(base / "outside" / "missing.stl", parts / "dangle");
    fs::create_symlink(parts / "loop2", parts / "loop1");
    fs::create_symlink(parts / "loop1", parts / "loop2");
    fs::create_directory_symlink(parts, base / "rootlink");
    confinement = {{parts.string()}, "part folders (test)"};
  }
  void TearDown() override { fs::remove_all(base); }

  bool inside(const std::string& requested) const { return confinePath(confinement, requested).inside; }

  fs::path base, parts;
  FolderConfinement confinement;
};

}  // namespace

TEST_F(ConfinedPathTest, InsidePathsResolveToWhatWillBeOpened) {
  const std::string a = fs::canonical(parts / "sub" / "a.stl").string();
  for (const std::string& request : {(parts / "sub" / "a.stl").string(), (parts / "in" / "a.stl").string(),
                                     (parts / "sub" / ".." / "sub" / "." / "a.stl").string(),
                                     (base / "outside" / ".." / "parts" / "sub" / "a.stl").string(),
                                     (parts / "out" / ".." / "parts" / "sub" / "a.stl").string(),  // out/.. is base
                                     std::string("sub/a.stl"), std::string("./in/./a.stl"),
                                     (base / "rootlink" / "sub" / "a.stl").string()}) {
    const ConfinedPath c = confinePath(confinement, request);
    ASSERT_TRUE(c.inside) << request << ": " << c.refusal;
    EXPECT_EQ(c.path, a) << request;
  }
  // The root itself, with or without a trailing slash, and a missing file inside it.
  EXPECT_TRUE(inside(parts.string()));
  EXPECT_TRUE(inside(parts.string() + "/"));
  EXPECT_TRUE(inside(parts.string() + "//sub//"));
  const ConfinedPath missing = confinePath(confinement, (parts / "sub" / "new.stl").string());
  ASSERT_TRUE(missing.inside);
  EXPECT_EQ(missing.path, (fs::canonical(parts) / "sub" / "new.stl").string());
}

TEST_F(ConfinedPathTest, EscapesAreRefused) {
  for (const std::string& request :
       {(parts / ".." / "outside" / "secret.stl").string(), (parts / "out" / "secret.stl").string(),
        (parts / "rel" / "secret.stl").string(), (parts / "dangle").string(),
        (parts / "missing" / ".." / ".." / "outside" / "secret.stl").string(),
        (parts / "in" / ".." / ".." / "outside" / "secret.stl").string(), (base / "partsx" / "b.stl").string(),
        (base / "partsx").string(), base.string(), std::string("../outside/secret.stl"),
        std::string("sub/../../outside"), (parts / "loop1").string(), std::string("/etc/shadow"),
        std::string("/etc/../etc/passwd"), std::string("/")}) {
    const ConfinedPath c = confinePath(confinement, request);
    EXPECT_FALSE(c.inside) << request << " -> " << c.path;
    EXPECT_EQ(c.refusal, outsideRefusal(confinement, request)) << request;
    EXPECT_TRUE(c.path.empty());
  }
}

TEST_F(ConfinedPathTest, RefusalSaysNothingAboutExistence) {
  // Same folder, one file there and one not: the two refusals differ only in the path they repeat.
  const std::string there = (base / "outside" / "secret.stl").string();
  const std::string not_there = (base / "outside" / "nothing.stl").string();
  const std::string r1 = confinePath(confinement, there).refusal;
  const std::string r2 = confinePath(confinement, not_there).refusal;
  EXPECT_EQ(r1.substr(r1.find("':")), r2.substr(r2.find("':")));
  EXPECT_EQ(r1.find("exist"), std::string::npos) << r1;
  EXPECT_EQ(r1.find("no such"), std::string::npos) << r1;
  EXPECT_NE(r1.find("path is outside the configured part folders"), std::string::npos) << r1;
  // A dangling link out and a live link out read the same as well.
  fs::create_symlink(base / "outside" / "secret.stl", parts / "live");
  const std::string live = confinePath(confinement, (parts / "live").string()).refusal;
  const std::string dangling = confinePath(confinement, (parts / "dangle").string()).refusal;
  EXPECT_EQ(live.substr(live.find("':")), dangling.substr(dangling.find("':")));
}

TEST_F(ConfinedPathTest, EmptyNulAndUnconfiguredAreRefused) {
  const ConfinedPath empty = confinePath(confinement, "");
  EXPECT_FALSE(empty.inside);
  EXPECT_FALSE(empty.refusal.empty());
  const std::string nul = (parts / "sub" / "a.stl").string() + std::string(1, '\0') + "/../../../outside";
  EXPECT_FALSE(inside(nul));
  const ConfinedPath none = confinePath({{}, "part folders"}, (parts / "sub" / "a.stl").string());
  EXPECT_FALSE(none.inside);
  EXPECT_NE(none.refusal.find("no part folders"), std::string::npos) << none.refusal;
  // Relative roots are ignored; with the absolute one after them, relative requests resolve under that one.
  const FolderConfinement mixed{{"relative/parts", parts.string()}, "part folders"};
  EXPECT_TRUE(confinePath(mixed, "sub/a.stl").inside);
  EXPECT_FALSE(confinePath({{"relative/parts"}, "part folders"}, "sub/a.stl").inside);
  // A refusal stays one line, however the request was written.
  const std::string noisy = confinePath(confinement, "/etc/\nshadow").refusal;
  EXPECT_EQ(noisy.find('\n'), std::string::npos) << noisy;
}

TEST_F(ConfinedPathTest, SeveralRootsAndALinkedRoot) {
  const FolderConfinement two{{(base / "rootlink").string() + "/", (base / "partsx").string()}, "part folders"};
  EXPECT_TRUE(confinePath(two, (parts / "sub" / "a.stl").string()).inside);
  EXPECT_TRUE(confinePath(two, (base / "partsx" / "b.stl").string()).inside);
  EXPECT_TRUE(confinePath(two, "sub/a.stl").inside);  // relative to the first root, through its link
  EXPECT_FALSE(confinePath(two, (base / "outside" / "secret.stl").string()).inside);
}

// Random requests built from the tree's names, `..`, `.` and empty elements: an accepted path that exists is exactly
// where the operating system's own resolution (realpath) lands, and lies inside the root; a refused path that exists
// resolves outside it; every refusal is the fixed outside text.
TEST_F(ConfinedPathTest, RandomRequestsAgreeWithTheOperatingSystem) {
  const std::vector<std::string> names{"sub", "..", ".", "out", "in", "rel", "dangle", "a.stl", "", "parts",
                                       "partsx", "outside", "secret.stl", "missing", "rootlink", "loop1"};
  const fs::path real_root = fs::canonical(parts);
  std::mt19937 random(18);
  int accepted = 0, refused = 0;
  for (int i = 0; i < 4000; ++i) {
    std::string request = random() % 3 == 0 ? "" : (random() % 2 ? parts.string() : base.string());
    const int n = 1 + static_cast<int>(random() % 6);
    for (int k = 0; k < n; ++k) request += (request.empty() ? "" : "/") + names[random() % names.size()];
    if (request.empty()) continue;
    const ConfinedPath c = confinePath(confinement, request);
    const fs::path absolute = fs::path(request).is_absolute() ? fs::path(request) : parts / request;
    std::error_code error;
    const fs::path real = fs::canonical(absolute, error);  // error: missing, or a loop
    if (c.inside) {
      ++accepted;
      EXPECT_TRUE(isInsideFolder(c.path, real_root)) << request << " -> " << c.path;
      if (!error) {
        EXPECT_EQ(c.path, real.string()) << request;
      }
    } else {
      ++refused;
      EXPECT_EQ(c.refusal, outsideRefusal(confinement, request)) << request;
      if (!error) {
        EXPECT_FALSE(isInsideFolder(real, real_root)) << request << " -> " << real;
      }
    }
  }
  EXPECT_GT(accepted, 200);
  EXPECT_GT(refused, 200);
}

TEST(ConfinedPath, InsideFolderComparesWholeElements) {
  EXPECT_TRUE(isInsideFolder("/a/b", "/a/b"));
  EXPECT_TRUE(isInsideFolder("/a/b/c", "/a/b"));
  EXPECT_TRUE(isInsideFolder("/a/b/c", "/a/b/"));
  EXPECT_FALSE(isInsideFolder("/a/bc", "/a/b"));
  EXPECT_FALSE(isInsideFolder("/a/bc/d", "/a/b"));
  EXPECT_FALSE(isInsideFolder("/a", "/a/b"));
  EXPECT_TRUE(isInsideFolder("/a", "/"));
}
