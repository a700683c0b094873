// One HDF5 library per process (issue 5): Debian ships HDF5 in flavours (serial, openmpi, mpich)
// that are separate libraries; ParaView's VTK links the openmpi one, netcdf and gdal the serial
// one. Recording a session must not add a second flavour of its own: after BMSession has written
// and read an .h5 file, the libhdf5 flavours mapped into this process (/proc/self/maps) are
// exactly one.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <set>
#include <string>

#include <unistd.h>

#include "bmSessionRecorder.h"

namespace {

/// Flavours of libhdf5 mapped into this process ("serial", "openmpi", "mpich", or "plain" for an
/// unsuffixed libhdf5.so), high-level and C++ wrappers counted with their flavour.
std::set<std::string> MappedHdf5Flavours() {
  std::set<std::string> out;
  std::ifstream maps("/proc/self/maps");
  const std::regex lib(R"(/libhdf5(_hl|_cpp)?(_(serial|openmpi|mpich))?(_hl|_cpp)?\.so)");
  std::string line;
  while (std::getline(maps, line)) {
    std::smatch m;
    if (std::regex_search(line, m, lib))
      out.insert(m[3].matched ? m[3].str() : "plain");
  }
  return out;
}

TEST(Hdf5Library, RecordingLoadsExactlyOneFlavour) {
  if (!bm::HasHdf5())
    GTEST_SKIP() << "built without HDF5";
  const auto dir =
      std::filesystem::temp_directory_path() / ("bm_hdf5_flavour_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  bm::Recording rec;
  rec.meta = {{"scene", "test"}};
  rec.frames.resize(3);
  const std::string h5 = (dir / "s.h5").string();
  bm::WriteRecording(h5, rec);
  EXPECT_EQ(bm::ReadRecording(h5).frames.size(), 3u);
  std::filesystem::remove_all(dir);
  const std::set<std::string> flavours = MappedHdf5Flavours();
  std::string list;
  for (const auto& f : flavours)
    list += " " + f;
  std::cout << "[hdf5] flavours mapped:" << list << "\n";
  EXPECT_EQ(flavours.size(), 1u) << "libhdf5 flavours in one process:" << list;
}

} // namespace
