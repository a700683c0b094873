// The hostile-input corpus for recordings (Docs/Reliability.md, "Recordings"): a header nested
// too deep is refused with the limit in the message, in the CSV and the HDF5 form.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "bmJson.h"
#include "bmSessionRecorder.h"

namespace {

namespace fs = std::filesystem;

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
  fs::path path = fs::temp_directory_path() / ("bm_hostile_rec_" + std::to_string(::getpid()));
  ScratchDir() { fs::create_directories(path); }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

TEST(HostileRecording, AHeaderNestedTooDeepIsRefused) {
  ScratchDir dir;
  const std::string csv = (dir.path / "deep.csv").string();
  {
    std::ofstream out(csv);
    out << "# bmsession {\"scene\": " << std::string(100000, '[') << std::string(100000, ']')
        << "}\n";
  }
  std::string why = Refusal([&] { bm::ReadRecording(csv); });
  EXPECT_TRUE(Has(why, "the header of recording '" + csv + "' (line 1) is nested deeper than 64"))
      << why;
  const std::string bad = (dir.path / "bad.csv").string();
  std::ofstream(bad) << "# bmsession {\"scene\": \n";
  why = Refusal([&] { bm::ReadRecording(bad); });
  EXPECT_TRUE(Has(why, "the header of recording '" + bad + "' (line 1) is not valid JSON")) << why;
  if (bm::HasHdf5()) {
    // 200 levels: deep enough to be refused, shallow enough for the writer's recursive dump.
    bm::Recording r;
    nlohmann::json deep = 1;
    for (int i = 0; i < 200; ++i)
      deep = nlohmann::json::array({deep});
    r.meta = {{"scene", deep}};
    const std::string h5 = (dir.path / "deep.h5").string();
    bm::WriteRecording(h5, r);
    why = Refusal([&] { bm::ReadRecording(h5); });
    EXPECT_TRUE(Has(why, "the header of recording '" + h5 + "' is nested deeper than 64")) << why;
  }
}

} // namespace
