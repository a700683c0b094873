// The hostile-input corpus for scenes and other JSON the project reads (Docs/Reliability.md,
// "Scenes and JSON"): documents nested too deep, refused with the limit in the message before the
// deep part is built (a scene nested 100 000 deep overflowed the stack).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "bmJson.h"
#include "bmScene.h"
#include "../bmTestRefusal.h"

namespace {

namespace fs = std::filesystem;

// `depth` nested arrays around 1: "[[[1]]]" for 3.
std::string Nested(int depth, char open = '[', char close = ']') {
  std::string s(size_t(depth), open);
  s += "1";
  s.append(size_t(depth), close);
  return s;
}

// `depth` nested objects {"a":{"a":...1}}.
std::string NestedObjects(int depth) {
  std::string s;
  for (int i = 0; i < depth; ++i)
    s += "{\"a\":";
  s += "1";
  s.append(size_t(depth), '}');
  return s;
}

using bmtest::Has;
using bmtest::Refusal;

struct ScratchDir : bmtest::ScratchDir {
  ScratchDir() : bmtest::ScratchDir("bm_hostile_scene") {}
  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return (path / name).string();
  }
};

TEST(HostileJson, NestingUpToTheLimitParsesDeeperIsRefusedWithTheLimit) {
  EXPECT_EQ(bm::ParseJson(Nested(bm::kMaxJsonDepth), "doc").dump().size(),
            size_t(2 * bm::kMaxJsonDepth + 1));
  EXPECT_TRUE(bm::ParseJson(NestedObjects(bm::kMaxJsonDepth), "doc").is_object());
  for (const std::string& text :
       {Nested(bm::kMaxJsonDepth + 1), NestedObjects(bm::kMaxJsonDepth + 1), Nested(100000),
        NestedObjects(100000), Nested(100000, '[', ' ') /* never closed */,
        "{\"name\": \"x\", \"tool\": " + Nested(100000) + "}"}) {
    const std::string why = Refusal([&] { bm::ParseJson(text, "document 'd.json'"); });
    EXPECT_TRUE(Has(why, "document 'd.json' is nested deeper than 64 levels")) << why;
  }
  std::istringstream stream(Nested(100000));
  EXPECT_TRUE(Has(Refusal([&] { bm::ParseJson(stream, "stream"); }), "nested deeper than 64"));
  // Not JSON at all: the parser's message, with the document named.
  EXPECT_TRUE(
      Has(Refusal([] { bm::ParseJson("{\"a\": ", "doc 'x'"); }), "doc 'x' is not valid JSON: "));
  EXPECT_THROW(bm::ParseJson("1", "doc", 0), std::invalid_argument);
}

TEST(HostileJson, SceneFilesNestedTooDeepAreRefusedNamingTheFile) {
  ScratchDir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"deep-array.json", Nested(100000)},
      {"deep-object.json", NestedObjects(100000)},
      {"deep-tool.json", "{\"name\": \"x\", \"tool\": " + Nested(100000) + "}"},
      {"deep-planning.json", "{\"planning\": " + NestedObjects(70) + "}"},
      {"deep-unclosed.json", std::string(100000, '[')},
  };
  for (const auto& [name, text] : cases) {
    const std::string path = dir.Write(name, text);
    const std::string why = Refusal([&] { bm::Scene::Load(path); });
    EXPECT_TRUE(Has(why, "scene file '" + path + "' is nested deeper than 64 levels"))
        << name << ": " << why;
  }
  // A scene within the limit still loads.
  const std::string ok =
      dir.Write("ok.json", "{\"name\": \"ok\", \"planning\": " + NestedObjects(20) + "}");
  EXPECT_EQ(bm::Scene::Load(ok).name, "ok");
}

// Every scene field that reaches the physics or names an output is checked, with the range or
// the rule in the message.
TEST(HostileScene, FieldsOutOfRangeAndNamesThatLeaveTheOutputFolderAreRefused) {
  using json = nlohmann::json;
  const json reamer = {{"type", "reamer"}};
  const std::vector<std::pair<json, std::string>> cases = {
      {{{"name", "../../x"}}, "field 'name' in scene must not start with '.'"},
      {{{"name", "a/../../x"}}, "field 'name' in scene must not contain '/'"},
      {{{"name", "/etc/x"}}, "must not contain '/'"},
      {{{"name", ".."}}, "field 'name' in scene must not start with '.'"},
      {{{"name", ".hidden"}}, "must not start with '.'"},
      {{{"name", "a\nb"}}, "control characters"},
      {{{"name", ""}}, "field 'name' in scene must have 1 to 128 characters, got 0"},
      {{{"name", std::string(129, 'x')}}, "must have 1 to 128 characters, got 129"},
      {{{"steps", json::array({{{"name", "../up"}}})}},
       "field 'name' in step 1 must not start with '.'"},
      {{{"steps", json::array({{{"name", "a/b"}}})}},
       "field 'name' in step 1 must not contain '/'"},
      {{{"tool", {{"type", "reamer"}, {"lips", 10000}}}},
       "tool parameter 'lips' must be in [1, 64], got 10000"},
      {{{"tool", {{"type", "drill"}, {"lips", 0}}}}, "tool parameter 'lips' must be >= 1"},
      {{{"tool", {{"type", "drill"}, {"radius_mm", 1e300}}}},
       "tool parameter 'radius' must be at most 1000 mm"},
      {{{"tool", {{"type", "reamer"}, {"alpha_deg", 95.0}}}},
       "tool parameter 'alpha_deg' must be in"},
      {{{"tool", {{"type", "reamer"}, {"nipple_length_mm", -1.0}}}},
       "tool parameter 'nipple_length' must be in"},
      {{{"trial", {{"entry_mm", {0, 0, 1e300}}}}}, "field 'entry_mm' in trial (mm) must be in"},
      {{{"trial", {{"feed_mm_per_rev", -0.1}}}},
       "field 'feed_mm_per_rev' in trial (feed) must be in"},
      {{{"trial", {{"speed_rpm", 1e9}}}}, "field 'speed_rpm' in trial (spindle speed) must be in"},
      {{{"voxmap_resolution", 100000}}, "field 'voxmap_resolution' (voxmap resolution) must be in"},
      {{{"bone", {{"material", -1.0}}}}, "field 'material' in bone (material scale) must be in"},
      {{{"bone", {{"material", 1e38}}}}, "field 'material' in bone (material scale) must be in"},
      {{{"voxmap_resolution", 1e300}},
       "field 'voxmap_resolution' in scene must be a whole number within the integers, got 1e+300"},
      {{{"threads", 10000000000LL}}, "field 'threads' in scene must be a whole number"},
      {{{"shell_resolution", 256.5}}, "field 'shell_resolution' in scene must be a whole number"},
      {{{"tool", {{"type", "reamer"}, {"lips", 1e300}}}},
       "tool field 'lips' must be a whole number within the integers"},
  };
  for (const auto& [j, expected] : cases) {
    const std::string why = Refusal([&] { bm::Scene::FromJson(j); });
    EXPECT_TRUE(Has(why, expected)) << j.dump() << ": " << why;
  }
  // A plan's step scene is named "<scene>: <step>" (not a folder: steps are numbered).
  const bm::Scene plan =
      bm::Scene::FromJson({{"name", std::string(128, 'p')},
                           {"steps", json::array({{{"name", std::string(64, 's')}}})}});
  EXPECT_EQ(plan.Step(0).name, std::string(128, 'p') + ": " + std::string(64, 's'));
  EXPECT_EQ(bm::Scene::FromJson({{"name", "glenoid reaming 2"}}).name, "glenoid reaming 2");
}

} // namespace
