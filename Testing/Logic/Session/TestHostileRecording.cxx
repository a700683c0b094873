// The hostile-input corpus for recordings (Docs/Reliability.md, "Recordings"): a header nested
// too deep is refused with the limit in the message, in the CSV and the HDF5 form; session fields
// out of range, too many frames, an endless line, a FIFO; recordings that cannot be replayed.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "bmJson.h"
#include "bmReplay.h"
#include "bmSessionRecorder.h"
#include "../bmTestRefusal.h"

#ifdef BM_TEST_HDF5
#include <hdf5.h>
#endif

#include <sys/stat.h>

namespace {

namespace fs = std::filesystem;

using bmtest::Has;
using bmtest::Refusal;

struct ScratchDir : bmtest::ScratchDir {
  ScratchDir() : bmtest::ScratchDir("bm_hostile_rec") {}
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

TEST(HostileRecording, SessionFieldsOutOfRangeAreRefusedWithTheRange) {
  const std::vector<std::pair<nlohmann::json, std::string>> cases = {
      {{{"sdf_resolution", 4096}},
       "the recording's session field 'sdf_resolution' must be in [8, 512], got 4096"},
      {{{"max_iterations", 1e9}}, "field 'max_iterations' must be in [1, 1000]"},
      {{{"rate_hz", 0}}, "field 'rate_hz' must be in [1, 1e+07], got 0"},
      {{{"force_scale", -2}}, "field 'force_scale' must be in [0.001, 1000], got -2"},
      {{{"max_step_voxels", 0}}, "field 'max_step_voxels' must be in (0, 100], got 0"},
      {{{"speed_rpm", "fast"}}, "field 'speed_rpm' must be a number"},
      {{{"method", "magic"}}, "the recording's session: contact method must be cutting or kim"},
      {{{"device_limits", {{"max_force_N", 1e6}}}},
       "the recording's device_limits field 'max_force_N' must be in (0, 100], got 1e+06"},
      {{{"device_limits", 3}}, "the recording's device_limits must be a JSON object"},
      {nlohmann::json::array(), "the recording's session must be a JSON object"},
  };
  for (const auto& [j, expected] : cases) {
    bm::DeviceLimits limits;
    const std::string why = Refusal([&] { bm::SessionOptionsFromJson(j, limits); });
    EXPECT_TRUE(Has(why, expected)) << j.dump() << ": " << why;
  }
  // What a session writes reads back.
  bm::DeviceLimits limits;
  const nlohmann::json written = bm::SessionOptionsToJson(bm::SessionOptions{}, limits);
  EXPECT_NO_THROW(bm::SessionOptionsFromJson(written, limits));
}

TEST(HostileRecording, FilesThatAreTooLongNotFilesOrNotReplayableAreRefused) {
  ScratchDir dir;
  bm::Recording r;
  r.meta = {{"scene", nlohmann::json::object()}};
  for (int i = 0; i < 3; ++i) {
    bm::FrameRecord f;
    f.frame = i;
    r.frames.push_back(f);
  }
  const std::string csv = (dir.path / "three.csv").string();
  bm::WriteRecording(csv, r);
  EXPECT_EQ(bm::ReadRecording(csv).frames.size(), 3u);
  std::string why = Refusal([&] { bm::ReadRecording(csv, 2); });
  EXPECT_TRUE(Has(why, "'" + csv + "' holds more than 2 frames")) << why;
  EXPECT_THROW(bm::ReadRecording(csv, 0), std::invalid_argument);
  if (bm::HasHdf5()) {
    const std::string h5 = (dir.path / "three.h5").string();
    bm::WriteRecording(h5, r);
    why = Refusal([&] { bm::ReadRecording(h5, 2); });
    EXPECT_TRUE(Has(why, "'" + h5 + "' declares 3 frames; at most 2 are read")) << why;
  }
  // A line without end: refused at the limit, not read whole.
  const std::string endless = (dir.path / "endless.csv").string();
  {
    std::ofstream out(endless);
    out << "# bmsession {}\n" << std::string(bm::kMaxRecordingLineBytes + 10, '1');
  }
  why = Refusal([&] { bm::ReadRecording(endless); });
  EXPECT_TRUE(Has(why, endless + ":2: line longer than 16777216 bytes")) << why;
  const std::string fifo = (dir.path / "fifo.csv").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  why = Refusal([&] { bm::ReadRecording(fifo); });
  EXPECT_TRUE(Has(why, "is not a regular file")) << why;
  why = Refusal([&] { bm::ReadRecording(dir.path.string()); });
  EXPECT_TRUE(Has(why, "is not a regular file")) << why;
  // Whole-number columns: NaN or a huge value would be undefined as an integer.
  const std::string header = "# bmsession {}\n";
  for (const auto& [row, expected] : std::vector<std::pair<std::string, std::string>>{
           {"nan", "column 'frame' must be a whole number in [0, 9e+15], got nan"},
           {"1e300", "column 'frame' must be a whole number in [0, 9e+15], got 1e+300"},
           {"0.5", "column 'frame' must be a whole number"}}) {
    bm::FrameRecord f;
    std::vector<double> cells = f.ToRow();
    std::string line = row;
    for (size_t i = 1; i < cells.size(); ++i)
      line += ",0";
    const std::string bad = (dir.path / "bad-frame.csv").string();
    std::ofstream(bad) << header << line << "\n";
    why = Refusal([&] { bm::ReadRecording(bad); });
    EXPECT_TRUE(Has(why, bad + ":2: " + expected)) << why;
  }
  bm::FrameRecord f;
  std::vector<double> cells = f.ToRow();
  cells.back() = -1; // flags
  EXPECT_TRUE(Has(Refusal([&] { bm::FrameRecord::FromRow(cells); }),
                  "column 'flags' must be a whole number in [0, 4.29497e+09], got -1"));
  // Replay refuses what it cannot reproduce: no frames, a non-finite recorded force.
  bm::Recording empty = r;
  empty.frames.clear();
  EXPECT_TRUE(Has(Refusal([&] { bm::CheckReplayable(empty); }), "the recording has no frames"));
  bm::Recording nanThrust = r;
  nanThrust.frames[1].thrustN = std::nan("");
  EXPECT_TRUE(Has(Refusal([&] { bm::CheckReplayable(nanThrust); }),
                  "frame 1 of the recording has a non-finite thrust"));
}

#ifdef BM_TEST_HDF5
/// A string attribute as the recorder writes "meta".
void PutStringAttribute(hid_t obj, const char* name, const std::string& value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size());
  H5Tset_strpad(type, H5T_STR_NULLPAD);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, type, value.data());
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
}

// An HDF5 recording whose /frames lives elsewhere (external storage naming another file, or a link
// to another file's dataset) is refused before a byte of it is read: the replay would read the
// named file and print its values.
TEST(HostileRecording, AnHdf5RecordingWhoseFramesLiveElsewhereIsRefused) {
  ScratchDir dir;
  const size_t ncols = bm::FrameRecord::Columns().size();
  const std::string secret = (dir.path / "secret.bin").string();
  std::ofstream(secret) << std::string(3 * ncols * 8, 'S');
  const std::string external = (dir.path / "external.h5").string();
  {
    const hid_t file = H5Fcreate(external.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    PutStringAttribute(file, "meta", "{\"scene\": {}}");
    const hsize_t dims[2] = {3, hsize_t(ncols)};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_external(dcpl, secret.c_str(), 0, hsize_t(3 * ncols * 8));
    const hid_t ds =
        H5Dcreate2(file, "frames", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ASSERT_GE(ds, 0);
    H5Dclose(ds);
    H5Pclose(dcpl);
    H5Sclose(space);
    H5Fclose(file);
  }
  std::string why = Refusal([&] { bm::ReadRecording(external); });
  EXPECT_TRUE(Has(why, "external storage")) << why;
  EXPECT_FALSE(Has(why, "SSSS")) << why;
  // /frames as a link into another recording.
  bm::Recording r;
  r.meta = {{"scene", nlohmann::json::object()}};
  r.frames.resize(2);
  r.frames[1].frame = 1;
  const std::string other = (dir.path / "other.h5").string();
  bm::WriteRecording(other, r);
  const std::string linked = (dir.path / "linked.h5").string();
  {
    const hid_t file = H5Fcreate(linked.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    PutStringAttribute(file, "meta", "{\"scene\": {}}");
    ASSERT_GE(
        H5Lcreate_external(other.c_str(), "/frames", file, "frames", H5P_DEFAULT, H5P_DEFAULT), 0);
    H5Fclose(file);
  }
  why = Refusal([&] { bm::ReadRecording(linked); });
  EXPECT_TRUE(Has(why, "is a link")) << why;
  EXPECT_EQ(bm::ReadRecording(other).frames.size(), 2u); // the control reads
}
#endif

} // namespace
