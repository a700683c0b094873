// Fuzz target: a scene file's text through bm::ParseJson (depth limit) and bm::Scene::FromJson
// (every field checked), then each plan step's scene.
#include <stdexcept>
#include <string_view>

#include "bmFuzzTarget.h"
#include "bmJson.h"
#include "bmScene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const nlohmann::json j =
        bm::ParseJson(std::string_view(reinterpret_cast<const char*>(data), size), "input");
    const bm::Scene s = bm::Scene::FromJson(j);
    for (size_t i = 0; i < s.steps.size(); ++i)
      (void)s.Step(i);
    (void)s.ToJson().dump();
  } catch (const std::exception&) {
    // refused: what the target expects of bad input
  }
  return 0;
}
