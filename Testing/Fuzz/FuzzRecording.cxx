// Fuzz target: a CSV session recording through bm::ReadRecording (header depth limit, frame and
// line limits), then what a replay checks before it runs: the scene, the session options and the
// frames (bm::RecordedScene, bm::SessionOptionsFromJson, bm::CheckReplayable).
#include <stdexcept>

#include "bmFuzzScratch.h"
#include "bmFuzzTarget.h"
#include "bmReplay.h"
#include "bmSessionRecorder.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bmfuzz::WriteInput("recording.csv", data, size);
  try {
    const bm::Recording r = bm::ReadRecording(path, 100000);
    bm::CheckReplayable(r);
    bm::DeviceLimits limits;
    (void)bm::SessionOptionsFromJson(r.meta.value("session", nlohmann::json::object()), limits);
    (void)bm::RecordedScene(r);
  } catch (const std::exception&) {
    // refused
  }
  return 0;
}
