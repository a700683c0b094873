// Bad input is refused with an exception naming what is wrong: scenes (bmScene.h), tools
// (bmToolModel.h MakeTool), voxmaps, and atomic saves into a folder that does not exist.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "bmAtomicFile.h"
#include "bmMemoryBudget.h"
#include "bmScene.h"
#include "bmToolModel.h"
#include "bmVoxmap.h"

namespace {

using json = nlohmann::json;

// Runs fn, expects E, and that its message contains every one of `words`.
template <class E>
void ExpectThrowNaming(const std::function<void()>& fn, const std::vector<std::string>& words,
                       const std::string& what) {
  try {
    fn();
    ADD_FAILURE() << what << ": no exception";
  } catch (const E& e) {
    const std::string msg = e.what();
    std::printf("%-32s -> %s\n", what.c_str(), msg.c_str());
    for (const auto& w : words)
      EXPECT_NE(msg.find(w), std::string::npos) << what << ": '" << msg << "' lacks '" << w << "'";
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": wrong exception type: " << e.what();
  }
}

void SceneRefuses(const json& j, const std::vector<std::string>& words, const std::string& what) {
  ExpectThrowNaming<std::invalid_argument>([&] { bm::Scene::FromJson(j); }, words, what);
}

TEST(BadInput, SceneFromJsonNamesTheField) {
  EXPECT_NO_THROW(bm::Scene::FromJson(json::object()));
  EXPECT_NO_THROW(bm::Scene::FromJson(bm::Scene{}.ToJson()));
  SceneRefuses({{"voxmap_resolutoin", 128}}, {"voxmap_resolutoin"}, "unknown field");
  SceneRefuses({{"trial", {{"feed", 0.02}}}}, {"feed", "trial"}, "unknown trial field");
  SceneRefuses({{"bone", {{"size", {1, 2, 3}}}}}, {"size", "bone"}, "unknown bone field");
  SceneRefuses({{"threads", "two"}}, {"threads"}, "wrong type (threads)");
  SceneRefuses({{"voxmap_resolution", "high"}}, {"voxmap_resolution"}, "wrong type (resolution)");
  SceneRefuses({{"trial", {{"speed_rpm", "fast"}}}}, {"speed_rpm"}, "wrong type (speed)");
  SceneRefuses({{"trial", {{"axis", {0, 1}}}}}, {"axis"}, "axis of 2 numbers");
  SceneRefuses({{"voxmap_resolution", 3}}, {"voxmap_resolution"}, "voxmap resolution 3");
  SceneRefuses({{"voxmap_resolution", 5000}}, {"voxmap_resolution"}, "voxmap resolution 5000");
  SceneRefuses({{"shell_resolution", 0}}, {"shell_resolution"}, "shell resolution 0");
  SceneRefuses({{"threads", 0}}, {"threads"}, "threads 0");
  SceneRefuses({{"trial", {{"feed_mm_per_rev", -0.02}}}}, {"feed_mm_per_rev"}, "negative feed");
  SceneRefuses({{"method", "vps"}}, {"method", "vps"}, "bad method");
  SceneRefuses({{"lips", "both"}}, {"lips"}, "bad lips");
  SceneRefuses({{"backend", "cuda"}}, {"backend"}, "bad backend");
  SceneRefuses({{"bone", {{"type", "wood"}}}}, {"type", "wood"}, "bad bone type");
  SceneRefuses({{"tool", {{"type", "drill"}, {"radius_mm", -1.0}}}}, {"radius"}, "tool in a scene");
  SceneRefuses(json::array(), {"object"}, "scene not an object");
}

TEST(BadInput, SceneFilesAndBuiltins) {
  ExpectThrowNaming<std::invalid_argument>([] { bm::Scene::Builtin("no-such-scene"); },
                                           {"no-such-scene", "drilling"}, "unknown built-in scene");
  const auto dir =
      std::filesystem::temp_directory_path() / ("bm-badinput-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto bad = dir / "bad.json";
  std::ofstream(bad) << "{ \"name\": \"x\", ";
  ExpectThrowNaming<std::runtime_error>([&] { bm::Scene::Load(bad.string()); },
                                        {"bad.json", "JSON"}, "malformed scene file");
  ExpectThrowNaming<std::runtime_error>([&] { bm::Scene::Load((dir / "missing.json").string()); },
                                        {"missing.json"}, "missing scene file");
  std::filesystem::remove_all(dir);
}

void ToolRefuses(const json& j, const std::vector<std::string>& words, const std::string& what) {
  ExpectThrowNaming<std::invalid_argument>([&] { bm::MakeTool(j); }, words, what);
}

TEST(BadInput, MakeToolNamesTheParameter) {
  EXPECT_EQ(bm::MakeTool({{"type", "drill"}})->Kind(), "drill");
  EXPECT_EQ(bm::MakeTool({{"type", "reamer"}})->Kind(), "reamer");
  EXPECT_EQ(bm::MakeTool({{"type", "burr"}, {"radius_mm", 3.0}})->Kind(), "burr");
  ToolRefuses({{"type", "chisel"}}, {"chisel"}, "unknown tool type");
  ToolRefuses({{"type", "drill"}, {"radius_mm", -1.0}}, {"radius"}, "negative radius");
  ToolRefuses({{"type", "drill"}, {"radius_mm", "wide"}}, {"radius_mm", "type"},
              "radius of wrong type");
  ToolRefuses({{"type", "drill"}, {"point_angle_deg", 95.0}}, {"point_angle_deg"},
              "point angle 95");
  ToolRefuses({{"type", "drill"}, {"lips", 0}}, {"lips"}, "no lips");
  ToolRefuses({{"type", "drill"}, {"web_half_width_mm", 2.0}}, {"web_half_width"},
              "web wider than drill");
  ToolRefuses({{"type", "drill"}, {"flute_length_mm", 0.1}}, {"flute_length"},
              "flute shorter than tip");
  ToolRefuses({{"type", "drill"}, {"nipple_radius_mm", 1.0}}, {"nipple_radius_mm"},
              "reamer field on a drill");
  ToolRefuses({{"type", "reamer"}, {"nipple_radius_mm", 30.0}}, {"nipple_radius"},
              "nipple wider than reamer");
  ToolRefuses({{"type", "reamer"}, {"outer_radius_mm", 40.0}}, {"outer_radius"},
              "rim beyond the arc");
  ToolRefuses(json::array(), {"object"}, "tool not an object");
}

TEST(BadInput, VoxmapRefusesNonPositiveGeometry) {
  for (std::array<int, 3> dims : {std::array<int, 3>{0, 4, 4}, {4, -1, 4}, {4, 4, 0}})
    ExpectThrowNaming<std::invalid_argument>(
        [&] {
          bm::Voxmap(dims, 0.1, {0, 0, 0});
        },
        {"dimension"},
        "voxmap dims " + std::to_string(dims[0]) + "," + std::to_string(dims[1]) + "," +
            std::to_string(dims[2]));
  for (double h : {0.0, -0.1, std::nan("")})
    ExpectThrowNaming<std::invalid_argument>(
        [&] {
          bm::Voxmap({4, 4, 4}, h, {0, 0, 0});
        },
        {"spacing"}, "voxmap spacing " + std::to_string(h));
  EXPECT_NO_THROW(bm::Voxmap({1, 1, 1}, 0.1, {0, 0, 0}));
}

TEST(BadInput, AtomicWriteIntoMissingFolderThrowsAndLeavesNothing) {
  const auto root =
      std::filesystem::temp_directory_path() / ("bm-atomic-" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root);
  const auto missing = root / "missing" / "summary.json";
  ExpectThrowNaming<std::runtime_error>(
      [&] { bm::WriteFileAtomic(missing.string(), std::string("{}")); }, {"summary.json"},
      "atomic write into missing folder");
  EXPECT_FALSE(std::filesystem::exists(root / "missing"));
  EXPECT_TRUE(std::filesystem::is_empty(root));

  // A writer that throws leaves the old file as it was and no temporary file beside it.
  const auto target = root / "forces.csv";
  bm::WriteFileAtomic(target.string(), std::string("old\n"));
  EXPECT_THROW(bm::WriteFileAtomic(target.string(),
                                   [](std::ostream& out) {
                                     out << "half";
                                     throw std::runtime_error("writer failed");
                                   }),
               std::runtime_error);
  std::ifstream in(target);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "old");
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(root)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
  // A successful save replaces the content.
  bm::WriteFileAtomic(target.string(), std::string("new\n"));
  std::ifstream in2(target);
  std::getline(in2, line);
  EXPECT_EQ(line, "new");
  std::filesystem::remove_all(root);
}

} // namespace

namespace {

// A voxmap larger than the memory budget is refused with a message before it is allocated (a
// block scene at --voxmap-resolution 2400 was killed by the kernel, 3000 .. 4096 failed with
// std::bad_alloc).
TEST(BadInput, AVoxmapLargerThanTheMemoryBudgetIsRefusedByName) {
  ExpectThrowNaming<std::runtime_error>(
      [] {
        bm::Voxmap v({4096, 4096, 4096}, 0.01, {0, 0, 0});
      },
      {"the voxmap (4096 x 4096 x 4096 voxels)", "more than"}, "a 4096^3 voxmap");
}

// The default budget follows the control group's limit (cgroup v2 and v1, at the root and at the
// process's own group), not only the host's memory.
TEST(BadInput, TheMemoryBudgetFollowsTheControlGroupLimit) {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / ("bm-cgroup-" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "user.slice" / "app");
  std::ofstream(root / "self-v2") << "0::/user.slice/app\n";
  std::ofstream(root / "memory.max") << "max\n";
  std::ofstream(root / "user.slice" / "app" / "memory.max") << "2147483648\n";
  EXPECT_EQ(bm::CgroupMemoryLimit(root.string(), (root / "self-v2").string()), 2147483648u);
  fs::remove(root / "user.slice" / "app" / "memory.max");
  EXPECT_EQ(bm::CgroupMemoryLimit(root.string(), (root / "self-v2").string()), 0u); // "max"
  // cgroup v1: memory.limit_in_bytes under the memory controller; "unlimited" is a huge number.
  fs::create_directories(root / "memory" / "job");
  std::ofstream(root / "self-v1") << "4:memory:/job\n0::/\n";
  std::ofstream(root / "memory" / "memory.limit_in_bytes") << "9223372036854771712\n";
  std::ofstream(root / "memory" / "job" / "memory.limit_in_bytes") << "1073741824\n";
  EXPECT_EQ(bm::CgroupMemoryLimit(root.string(), (root / "self-v1").string()), 1073741824u);
  fs::remove_all(root);
  // This process's own budget is at most 75 % of its control group's limit, if it has one.
  const uint64_t group = bm::CgroupMemoryLimit();
  if (group > 0) {
    EXPECT_LE(bm::DefaultMemoryLimit(), group * 3 / 4 + 1);
  }
}

} // namespace
