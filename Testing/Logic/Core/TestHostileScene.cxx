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

std::string Refusal(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "accepted";
}

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

struct ScratchDir {
  fs::path path = fs::temp_directory_path() / ("bm_hostile_scene_" + std::to_string(::getpid()));
  ScratchDir() { fs::create_directories(path); }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
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

} // namespace
