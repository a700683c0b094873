// One HDF5 library per process: Debian ships HDF5 in flavours (serial, openmpi, mpich)
// that are separate libraries; ParaView's VTK links the openmpi one, netcdf and gdal the serial
// one. Recording a session must not add a second flavour of its own: after BMSession has written
// and read an .h5 file, the libhdf5 flavours mapped into this process (/proc/self/maps) are
// exactly one.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>

#include <unistd.h>

#include "bmSessionRecorder.h"

namespace {

/// The flavour of the libhdf5 a /proc/self/maps line maps ("serial", "openmpi", "mpich", or
/// "plain" for an unsuffixed libhdf5.so; the high-level and C++ wrappers count with their
/// flavour), or "" when the line maps no libhdf5. Parsed by hand: std::regex draws GCC 12's
/// false -Wmaybe-uninitialized from <regex> in the sanitizer build.
std::string Hdf5Flavour(const std::string& line) {
  const std::string stem = "/libhdf5";
  const size_t at = line.find(stem);
  if (at == std::string::npos)
    return "";
  const size_t so = line.find(".so", at + stem.size());
  if (so == std::string::npos)
    return "";
  // The suffixes between the stem and ".so": "", "_serial", "_serial_hl", "_hl_openmpi", ...
  const std::string suffixes = line.substr(at + stem.size(), so - at - stem.size());
  std::string flavour = "plain";
  size_t pos = 0;
  while (pos < suffixes.size()) {
    if (suffixes[pos] != '_')
      return "";
    const size_t next = std::min(suffixes.find('_', pos + 1), suffixes.size());
    const std::string part = suffixes.substr(pos + 1, next - pos - 1);
    if (part == "serial" || part == "openmpi" || part == "mpich")
      flavour = part;
    else if (part != "hl" && part != "cpp")
      return ""; // another library (libhdf5_fortran, ...)
    pos = next;
  }
  return flavour;
}

/// Flavours of libhdf5 mapped into this process (Hdf5Flavour of each line of the maps).
std::set<std::string> MappedHdf5Flavours() {
  std::set<std::string> out;
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line))
    if (const std::string f = Hdf5Flavour(line); !f.empty())
      out.insert(f);
  return out;
}

TEST(Hdf5Library, FlavourIsReadFromTheMappedFileName) {
  const std::string prefix = "7f00-7f10 r-xp 00000000 08:01 123 /usr/lib/x86_64-linux-gnu/";
  EXPECT_EQ(Hdf5Flavour(prefix + "libhdf5_serial.so.103.3.0"), "serial");
  EXPECT_EQ(Hdf5Flavour(prefix + "libhdf5_serial_hl.so.100.1.4"), "serial");
  EXPECT_EQ(Hdf5Flavour(prefix + "libhdf5_openmpi.so.103"), "openmpi");
  EXPECT_EQ(Hdf5Flavour("/usr/lib/x86_64-linux-gnu/hdf5/mpich/libhdf5_mpich_cpp.so"), "mpich");
  EXPECT_EQ(Hdf5Flavour(prefix + "libhdf5.so.310"), "plain");
  EXPECT_EQ(Hdf5Flavour(prefix + "libhdf5_hl.so"), "plain");
  EXPECT_EQ(Hdf5Flavour(prefix + "libhdf5_fortran.so.102"), "");
  EXPECT_EQ(Hdf5Flavour(prefix + "libhdf5serial.so"), "");
  EXPECT_EQ(Hdf5Flavour(prefix + "libvtkhdf5.so"), "");
  EXPECT_EQ(Hdf5Flavour(prefix + "libz.so.1"), "");
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
