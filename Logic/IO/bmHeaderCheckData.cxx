// bmHeaderCheckData.cxx - a volume's data: the detached data file a header names (kept beside
// the header unless allowed elsewhere) and whether it holds every byte the header declares, raw or
// inflated from gzip or zlib (bmHeaderCheckInternal.h).
#include "bmHeaderCheckInternal.h"

#include <zlib.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>

namespace fs = std::filesystem;

namespace bm::headercheck {

/// Resolve a detached data file named in a header, refusing paths that leave the header's folder.
fs::path DataFileBeside(const fs::path& header, const std::string& name,
                        const HeaderLimits& limits) {
  if (name.empty())
    throw std::runtime_error(Q(header) + " names an empty data file");
  if (name.find('%') != std::string::npos || name.rfind("LIST", 0) == 0)
    throw std::runtime_error(Q(header) + " names its data as a list or pattern of files ('" + name +
                             "'); only a single data file is supported");
  fs::path p(name);
  const fs::path folder = header.parent_path().empty() ? fs::path(".") : header.parent_path();
  if (!limits.allowDataOutsideFolder) {
    if (p.is_absolute())
      throw std::runtime_error(Q(header) + " names its data file by an absolute path ('" + name +
                               "'); data files must lie beside the header (allow other places "
                               "with --allow-outside-data)");
    for (const auto& part : p)
      if (part == "..")
        throw std::runtime_error(Q(header) + " names its data file with '..' ('" + name +
                                 "'); data files must lie beside the header (allow other places "
                                 "with --allow-outside-data)");
  }
  fs::path full = p.is_absolute() ? p : folder / p;
  CheckRegularFile(full, "the data file named by " + Q(header));
  if (!limits.allowDataOutsideFolder) {
    const fs::path dir = fs::canonical(folder), real = fs::canonical(full);
    auto rel = real.lexically_relative(dir);
    if (rel.empty() || *rel.begin() == "..")
      throw std::runtime_error(Q(header) + ": its data file '" + name +
                               "' leads (through a link) to " + Q(real) +
                               ", outside the header's folder (allow it with "
                               "--allow-outside-data)");
  }
  return full;
}

/// Bytes a gzip stream starting at `offset` of `file` inflates to, reading at most `need` bytes.
/// Throws when the stream is corrupt.
uint64_t GzipBytes(const fs::path& file, uint64_t offset, uint64_t need) {
  gzFile gz = gzopen(file.c_str(), "rb");
  if (!gz)
    throw std::runtime_error("cannot open " + Q(file));
  std::vector<char> buf(1 << 16);
  uint64_t total = 0;
  if (offset > 0) {
    // Skip the text header: open the file, seek past it, and inflate from there.
    gzclose(gz);
    int fd = ::open(file.c_str(), O_RDONLY);
    if (fd < 0 || ::lseek(fd, off_t(offset), SEEK_SET) != off_t(offset)) {
      if (fd >= 0)
        ::close(fd);
      throw std::runtime_error("cannot read " + Q(file));
    }
    gz = gzdopen(fd, "rb");
    if (!gz) {
      ::close(fd);
      throw std::runtime_error("cannot read " + Q(file));
    }
  }
  while (total < need) {
    int n = gzread(gz, buf.data(), unsigned(buf.size()));
    if (n < 0) {
      int err = 0;
      std::string msg = gzerror(gz, &err);
      gzclose(gz);
      throw std::runtime_error(Q(file) + ": its compressed data are corrupt (" + msg + ")");
    }
    if (n == 0)
      break;
    if (total == 0 && gzdirect(gz)) { // zlib passes data without a gzip header through as is
      gzclose(gz);
      throw std::runtime_error(Q(file) + ": its data are declared gzip but are not gzip data");
    }
    total += uint64_t(n);
  }
  gzclose(gz);
  return total;
}

/// Bytes a zlib (or gzip) stream of at most `maxIn` bytes starting at `offset` of `file` inflates
/// to, reading until `need` bytes came out or the stream or its bytes end. Throws when the stream
/// is corrupt. `complete` says whether the stream reached its end marker.
uint64_t ZlibBytes(const fs::path& header, const fs::path& file, uint64_t offset, uint64_t maxIn,
                   uint64_t need, bool& complete) {
  std::ifstream in(file, std::ios::binary);
  if (!in || !in.seekg(std::streamoff(offset)))
    throw std::runtime_error("cannot read " + Q(file));
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) // zlib or gzip header, as MetaIO's reader
    throw std::runtime_error("zlib cannot be initialised");
  std::vector<unsigned char> src(1 << 16), dst(1 << 16);
  uint64_t total = 0, read = 0;
  int rc = Z_OK;
  complete = false;
  while (total < need && rc != Z_STREAM_END) {
    if (z.avail_in == 0) {
      const uint64_t want = std::min<uint64_t>(src.size(), maxIn - read);
      if (want == 0)
        break;
      in.read(reinterpret_cast<char*>(src.data()), std::streamsize(want));
      const uint64_t got = uint64_t(in.gcount());
      if (got == 0)
        break;
      read += got;
      z.next_in = src.data();
      z.avail_in = unsigned(got);
    }
    z.next_out = dst.data();
    z.avail_out = unsigned(dst.size());
    rc = inflate(&z, Z_NO_FLUSH);
    total += dst.size() - z.avail_out;
    if (rc == Z_STREAM_END) {
      complete = true;
      break;
    }
    if (rc != Z_OK && rc != Z_BUF_ERROR) {
      const std::string msg = z.msg ? z.msg : "error " + std::to_string(rc);
      inflateEnd(&z);
      throw std::runtime_error(Q(header) + ": its compressed data are corrupt (zlib: " + msg + ")");
    }
    if (rc == Z_BUF_ERROR && z.avail_in != 0)
      break; // no progress possible
  }
  inflateEnd(&z);
  return total;
}

void CheckDataBytes(const fs::path& header, const fs::path& data, uint64_t offset, uint64_t need,
                    bool gzip) {
  uint64_t have = 0;
  if (gzip)
    have = GzipBytes(data, offset, need);
  else {
    uint64_t size = fs::file_size(data);
    have = size > offset ? size - offset : 0;
  }
  if (have < need)
    throw std::runtime_error(Q(header) + " is truncated: its voxels need " + std::to_string(need) +
                             " bytes, " + (data == header ? "the file" : Q(data)) + " holds " +
                             (gzip ? "(uncompressed) " : "") + std::to_string(have));
}

} // namespace bm::headercheck
