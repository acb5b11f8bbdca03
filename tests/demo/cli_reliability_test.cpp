// Bad input to the real polder program, one class at a time: every value the command line or
// a scene file takes is finite, in range and never wrapped; paths that are folders, DEMs with
// one row, coordinates far beyond any terrain and writers on a full disk all end in one line
// naming the option or file, exit 2 for usage and 1 for data, and no file at the destination.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <polder/terrain/image_writer.hpp>

#include "polder_run.hpp"
#include "test_support.hpp"

namespace polder::test {
namespace {

struct BadCase {
  std::string arguments;
  int exitCode;
  std::string mentions;  // the option, file or key the message must name
};

std::size_t lineCount(const std::string& text) {
  return std::size_t(std::count(text.begin(), text.end(), '\n')) + (!text.empty() && text.back() != '\n');
}

// Exit code, the name, one line, and nothing from a crash.
void expectRefused(const BadCase& c, const std::string& prefix = "") {
  const ProgramRun run = runPolder(c.arguments, prefix);
  EXPECT_EQ(run.exitCode, c.exitCode) << c.arguments << "\n" << run.output;
  EXPECT_NE(run.output.find(c.mentions), std::string::npos)
      << c.arguments << " should name '" << c.mentions << "': " << run.output;
  EXPECT_EQ(lineCount(run.output), 1u) << c.arguments << ": " << run.output;
  EXPECT_EQ(run.output.rfind("polder: error: ", 0), 0u) << c.arguments << ": " << run.output;
}

// An n x n grid of quads in x/y, as OBJ text.
std::string gridObj(int n) {
  std::string text;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      text += "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string((x * y) % 3) + "\n";
  const auto at = [n](int x, int y) { return std::to_string(y * (n + 1) + x + 1); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      text += "f " + at(x, y) + " " + at(x + 1, y) + " " + at(x + 1, y + 1) + "\n";
      text += "f " + at(x, y) + " " + at(x + 1, y + 1) + " " + at(x, y + 1) + "\n";
    }
  return text;
}

class PolderReliability : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    s_dir = new ScratchDir();
    const ProgramRun gen = runPolder("gen --size 65 --seed 3 --spacing 20 --out " + file("dem.png"));
    ASSERT_EQ(gen.exitCode, 0) << gen.output;
    writeFile(s_dir->file("grid.obj"), gridObj(30));
  }
  static void TearDownTestSuite() {
    delete s_dir;
    s_dir = nullptr;
  }
  static std::string file(const std::string& name) { return s_dir->file(name).string(); }
  static std::string dem() { return file("dem.png"); }
  static inline ScratchDir* s_dir = nullptr;
};

// Not finite, out of range, fractional where a count is meant, negative into an unsigned
// option: each command's numbers, refused as usage errors naming the option.
TEST_F(PolderReliability, NumbersOnTheCommandLineAreFiniteInRangeAndNeverWrapped) {
  const std::string out = " --out " + file("out.png");
  const std::string mesh = file("grid.obj");
  const std::vector<BadCase> cases = {
      {"flyover " + dem() + " --headless --frames 2 --speed inf" + out, 2, "--speed"},
      {"flyover " + dem() + " --headless --frames 2 --altitude -inf" + out, 2, "--altitude"},
      {"flyover " + dem() + " --headless --frames 2 --fps nan" + out, 2, "--fps"},
      {"flyover " + dem() + " --headless --frames 1e9" + out, 2, "--frames"},
      {"bench " + dem() + " --altitude nan", 2, "--altitude"},
      {"bench " + dem() + " --frames 0", 2, "--frames"},
      {"bench " + dem() + " --frames 2.5", 2, "--frames"},
      {"bench " + dem() + " --tau -1", 2, "--tau"},
      {"bench " + dem() + " --budget -1 --mode budget", 2, "--budget"},
      {"bench " + dem() + " --fov 180", 2, "--fov"},
      {"bench " + dem() + " --memory-mb 12", 2, "--memory-mb"},
      {"bench " + dem() + " --memory-mb 64 --cache-mb 8", 2, "--memory-mb"},
      {"flyover " + dem() + " --headless --frames 2 --memory-mb nan" + out, 2, "--memory-mb"},
      {"simplify " + mesh + " --triangles -1 --out " + file("o.obj"), 2, "--triangles"},
      {"simplify " + mesh + " --triangles 0 --out " + file("o.obj"), 2, "--triangles"},
      {"simplify " + mesh + " --triangles 1e400 --out " + file("o.obj"), 2, "--triangles"},
      {"simplify " + mesh + " --triangles 18446744073709551615 --out " + file("o.obj"), 2, "--triangles"},
      {"simplify " + mesh + " --triangles 100 --regions -3 --out " + file("o.obj"), 2, "--regions"},
      {"info " + dem() + " --spacing 1e300", 2, "--spacing"},
      {"info " + dem() + " --spacing nan", 2, "--spacing"},
      {"info " + dem() + " --zscale inf", 2, "--zscale"},
      {"render " + dem() + " --camera 0,0,100,0,400" + out, 2, "pitch"},
      {"render " + dem() + " --camera 0,0,100,0,-10 --tau nan" + out, 2, "--tau"},
      {"gen --size -5" + out, 2, "--size"},
      {"gen --size 65 --seed -1" + out, 2, "--seed"},
      {"gen --size 65 --spacing 0" + out, 2, "--spacing"},
      {"bench " + dem() + " --scene " + file("none.json"), 2, "a DEM"},
      {"bench --scene " + file("none.json") + " --tau 2", 2, "--tau"},
  };
  for (const BadCase& c : cases) expectRefused(c);
  EXPECT_FALSE(std::filesystem::exists(file("out.png")));
  EXPECT_FALSE(std::filesystem::exists(file("o.obj")));
}

// Positions far beyond any terrain (where single-precision ray tracing breaks down) are
// refused on the command line and in camera path files; the library itself sees nothing there.
TEST_F(PolderReliability, CoordinatesFarBeyondTheTerrainAreRefused) {
  writeFile(s_dir->file("far.path"), "0 1e18 0 500 0 -10\n1 2e18 0 500 0 -10\n");
  const std::vector<BadCase> cases = {
      {"query " + dem() + " --ray 1e18,0,100,0,0,-1", 2, "--ray"},
      {"query " + dem() + " --ray 100,100,100,1e300,0,-1", 2, "--ray"},
      {"query " + dem() + " --at nan,1", 2, "--at"},
      {"render " + dem() + " --camera -1e18,0,100,0,-10 --reference --out " + file("r.png"), 2, "--camera"},
      {"bench " + dem() + " --frames 2 --path " + file("far.path"), 1, "far.path"},
  };
  for (const BadCase& c : cases) expectRefused(c);
  EXPECT_FALSE(std::filesystem::exists(file("r.png")));
}

// Every number a scene file holds goes through the same rules as the command line, and the
// message names the scene file and the key.
TEST_F(PolderReliability, SceneFileNumbersFollowTheSameRules) {
  const std::string scene = file("bad.json");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({ "frames": 1e9 })", "frames"},
      {R"({ "frames": -1 })", "frames"},
      {R"({ "frames": 4294967297 })", "frames"},
      {R"({ "lod": { "budget": -1 } })", "lod.budget"},
      {R"({ "lod": { "tau": 0 } })", "lod.tau"},
      {R"({ "camera": { "pose": [0, 0, 100, 0, 400] } })", "camera.pose"},
      {R"({ "camera": { "pose": [1e18, 0, 100, 0, -10] } })", "camera.pose"},
      {R"({ "terrain": { "dem": ")" + dem() + R"(", "block": 3 } })", "terrain.block"},
      {R"({ "terrain": { "dem": ")" + dem() + R"(", "spacing": 1e300 } })", "terrain.spacing"},
      {R"({ "models": { "m": { "file": ")" + file("grid.obj") + R"(", "regions": 1e12 } } })", "models.m.regions"},
      {R"({ "models": { "m": { "file": ")" + file("grid.obj") + R"(", "regions": [5000, 2] } } })", "models.m.regions"},
      {R"({ "nodes": [ { "repeat": { "count": 1e9 } } ] })", "nodes[0].repeat.count"},
  };
  for (const auto& [text, key] : cases) {
    writeFile(scene, text);
    expectRefused({"scene " + scene, 1, "bad.json: " + key});
  }
}

// A folder where a file is expected, and DEMs of one row or column: data errors naming the
// path, from every command that reads them.
TEST_F(PolderReliability, FoldersAndOneRowDemsAreRefusedNamingThePath) {
  const std::string folder = s_dir->path().string();
  terrain::Heightfield row(1, 9, 10.0, 10.0);
  ASSERT_TRUE(terrain::writeHeightPng16(s_dir->file("row.png"), row).ok());
  writeFile(s_dir->file("column.r16"), std::string(18, '\1'));
  const std::string out = " --out " + file("never.png");
  const std::vector<BadCase> cases = {
      {"scene " + folder, 1, "is a directory"},
      {"info " + folder, 1, folder},
      {"simplify " + folder + " --triangles 10 --out " + file("o.obj"), 1, folder},
      {"info " + file("row.png"), 1, "row.png"},
      {"info " + file("row.png"), 1, "2 x 2"},
      {"query " + file("row.png") + " --at 0,0", 1, "row.png"},
      {"render " + file("row.png") + " --camera 0,0,100,0,-10" + out, 1, "row.png"},
      {"bench " + file("row.png") + " --frames 2", 1, "row.png"},
      {"prep " + file("row.png") + " --out " + file("row.pyr"), 1, "row.png"},
      {"info " + file("column.r16") + " --raw 9x1:u16", 1, "column.r16"},
  };
  for (const BadCase& c : cases) expectRefused(c);
  EXPECT_FALSE(std::filesystem::exists(file("never.png")));
  EXPECT_FALSE(std::filesystem::exists(file("row.pyr")));
}

// A write that the system refuses (here a file size limit, as a full disk would) is reported,
// and neither the destination nor a temporary file is left behind.
TEST_F(PolderReliability, WritersReportFailedWritesAndLeaveNoFile) {
  ScratchDir folder;
  const std::string limit = "trap '' XFSZ; ulimit -f 16; ";  // 8 to 16 KiB, by the shell's unit
  const auto path = [&](const char* name) { return folder.file(name).string(); };
  const std::vector<BadCase> cases = {
      {"gen --size 257 --seed 1 --out " + path("g.png"), 1, "g.png"},
      {"gen --size 257 --seed 1 --out " + path("g.tif"), 1, "g.tif"},
      {"render " + dem() + " --camera 600,-300,900,0,-30 --size 320x240 --out " + path("r.png"), 1, "r.png"},
      {"simplify " + file("grid.obj") + " --triangles 1500 --out " + path("s.obj"), 1, "s.obj"},
      {"mesh " + dem() + " --max-error 1 --out " + path("m.ply"), 1, "m.ply"},
      {"prep " + dem() + " --out " + path("p.pyr"), 1, "p.pyr"},
  };
  for (const BadCase& c : cases) {
    const ProgramRun run = runPolder(c.arguments, limit);
    EXPECT_EQ(run.exitCode, c.exitCode) << c.arguments << "\n" << run.output;
    EXPECT_NE(run.output.find("polder: error: " + folder.path().string()), std::string::npos)
        << c.arguments << ": " << run.output;
    EXPECT_NE(run.output.find(c.mentions), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("wrote"), std::string::npos) << run.output;
    const auto entries = std::distance(std::filesystem::directory_iterator(folder.path()), {});
    EXPECT_EQ(entries, 0) << c.arguments << " left a file behind";
  }
}

// Degenerate but valid terrain flies within tau and watertight: the smallest DEM, a flat one,
// and extreme but finite spacings; an impossible height scale is refused with its reason.
TEST_F(PolderReliability, DegenerateButValidDemsFlyAndImpossibleHeightsAreRefused) {
  writeFile(s_dir->file("two.r16"), std::string("\x10\x00\x20\x00\x30\x00\x40\x00", 8));
  writeFile(s_dir->file("flat.r16"), std::string(2 * 128 * 128, '\0'));
  const std::string flat = file("flat.r16") + " --raw 128x128:u16";
  for (const std::string& flight : {file("two.r16") + " --raw 2x2:u16", flat, flat + " --spacing 0.001",
                                    flat + " --spacing 1000000", dem() + " --zscale -10"}) {
    const ProgramRun run = runPolder("bench " + flight + " --frames 6 --measure-every 2");
    EXPECT_EQ(run.exitCode, 0) << flight << "\n" << run.output;  // 1 would be tau or a crack broken
  }
  expectRefused({"bench " + dem() + " --zscale 1000000", 1, "height scale"});
  expectRefused({"bench " + dem() + " --zscale -5000", 1, "dem.png"});
}

}  // namespace
}  // namespace polder::test
