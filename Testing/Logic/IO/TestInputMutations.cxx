// Deterministic mutation fuzzing of the CT readers (Docs/Reliability.md, "CT import"): valid small
// NRRD, MetaImage, NIfTI and DICOM inputs with random bytes changed or cut short (fixed seeds, so
// a failure reproduces). Every mutant must either read or be refused with std::runtime_error: no
// crash, no abort, no other exception type escaping bm::ReadCT. CI runs a few hundred mutants per
// format (about 5 s in all); BM_MUTATION_FACTOR=N runs N times as many, with other seeds, by hand.
#include "bmIOTestUtil.h"

#include "bmCTReader.h"

#include <gtest/gtest.h>

#include <zlib.h>

#include <cstring>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

using namespace bmtest;

namespace {

/// BM_MUTATION_FACTOR (default 1): more mutants and other seeds for a longer run by hand.
int Factor() {
  const char* f = std::getenv("BM_MUTATION_FACTOR");
  return f && std::atoi(f) > 0 ? std::atoi(f) : 1;
}

std::string Voxels() {
  std::string s;
  for (int i = 0; i < 64; ++i) {
    const int16_t v = (i >= 21 && i <= 42) ? 1000 : -1000;
    s.append(reinterpret_cast<const char*>(&v), 2);
  }
  return s;
}

std::string ReadBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void WriteBytes(const fs::path& p, const std::string& b) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(b.data(), std::streamsize(b.size()));
}

/// One mutant of `bytes`: a few bytes changed within the first `span` bytes, or the file cut.
std::string Mutate(std::string bytes, size_t span, std::mt19937& rng) {
  span = std::min(span, bytes.size());
  const int kind = int(rng() % 4);
  if (kind == 0) { // cut short
    bytes.resize(rng() % bytes.size());
    return bytes;
  }
  const int n = 1 + int(rng() % 4);
  static const char kChars[] = "0123456789-+.eEnNaAiIfF \n:=()/,\x00\xff";
  for (int i = 0; i < n; ++i) {
    const size_t at = rng() % span;
    if (kind == 1)
      bytes[at] = char(rng() % 256);
    else if (kind == 2)
      bytes[at] = kChars[rng() % (sizeof kChars - 1)];
    else
      bytes.insert(at, 1, kChars[rng() % (sizeof kChars - 1)]);
  }
  return bytes;
}

/// Read `file` expecting success or a std::runtime_error; counts refusals.
void ReadOrRefuse(const fs::path& file, const std::string& what, int& refused) {
  bm::ReadOptions opt;
  opt.maxMemoryBytes = 64 << 20;
  try {
    bm::ReadCT(file.string(), opt);
  } catch (const std::runtime_error&) {
    ++refused;
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": " << typeid(e).name() << " escaped: " << e.what();
  } catch (...) {
    ADD_FAILURE() << what << ": a non-standard exception escaped";
  }
}

void FuzzFile(const std::string& name, const std::string& valid, size_t span, int count,
              unsigned seed) {
  ScratchDir d("mutations-" + std::to_string(seed));
  std::mt19937 rng(seed * unsigned(Factor()));
  count *= Factor();
  int refused = 0;
  for (int i = 0; i < count; ++i) {
    const fs::path f = d / name;
    WriteBytes(f, Mutate(valid, span, rng));
    ReadOrRefuse(f, name + " mutant " + std::to_string(i) + " (seed " + std::to_string(seed) + ")",
                 refused);
  }
  EXPECT_GT(refused, 0) << name; // the mutations do reach the checks
}

} // namespace

TEST(InputMutations, Nrrd) {
  const std::string header =
      "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nspace: left-posterior-superior\n"
      "space directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\nendian: little\n"
      "encoding: raw\n\n";
  FuzzFile("m.nrrd", header + Voxels(), header.size(), 400, 1);
}

TEST(InputMutations, MetaImage) {
  const std::string header = "ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = "
                             "MET_SHORT\nElementSpacing = 1 1 1\nOffset = 0 0 0\nTransformMatrix "
                             "= 1 0 0 0 1 0 0 0 1\nElementDataFile = LOCAL\n";
  FuzzFile("m.mha", header + Voxels(), header.size(), 400, 2);
}

TEST(InputMutations, Nifti) {
  char h[352] = {};
  auto put16 = [&](int off, int16_t v) { std::memcpy(h + off, &v, 2); };
  auto putf = [&](int off, float v) { std::memcpy(h + off, &v, 4); };
  const int32_t size = 348;
  std::memcpy(h, &size, 4);
  const int16_t dim[8] = {3, 4, 4, 4, 1, 1, 1, 1};
  for (int i = 0; i < 8; ++i)
    put16(40 + 2 * i, dim[i]);
  put16(70, 4);
  put16(72, 16);
  for (int i = 0; i < 8; ++i)
    putf(76 + 4 * i, 1.0f);
  putf(108, 352);
  putf(112, 1);
  put16(252, 1); // qform
  put16(254, 1); // sform
  putf(280, 1);
  putf(300, 1);
  putf(320, 1);
  std::memcpy(h + 344, "n+1", 4);
  FuzzFile("m.nii", std::string(h, sizeof h) + Voxels(), 348, 400, 3);
}

TEST(InputMutations, DicomSlice) {
  ScratchDir d("mutations-dicom");
  WriteBlock(d / "ct");
  const auto files = SeriesFiles(d / "ct");
  const fs::path victim = files[files.size() / 2];
  const std::string valid = ReadBytes(victim);
  std::mt19937 rng(4u * unsigned(Factor()));
  int refused = 0;
  for (int i = 0; i < 200 * Factor(); ++i) {
    WriteBytes(victim, Mutate(valid, std::min<size_t>(valid.size(), 1200), rng));
    ReadOrRefuse(d / "ct", "DICOM slice mutant " + std::to_string(i), refused);
  }
  EXPECT_GT(refused, 0);
}

// A slice with sequences of undefined length (nested items, as real CTs carry them) before its
// image attributes: mutants over the sequences and the elements after them reach the element
// walk's sequence handling (GDCM aborts on damage after such a sequence).
TEST(InputMutations, DicomSliceWithSequences) {
  ScratchDir d("mutations-dicom-sq");
  WriteBlock(d / "ct");
  const auto files = SeriesFiles(d / "ct");
  for (const auto& f : files)
    EditDicom(f, AddUndefinedLengthSequence);
  const fs::path victim = files[files.size() / 2];
  const std::string valid = ReadBytes(victim);
  std::mt19937 rng(5u * unsigned(Factor()));
  int refused = 0;
  for (int i = 0; i < 200 * Factor(); ++i) {
    WriteBytes(victim, Mutate(valid, std::min<size_t>(valid.size(), 1500), rng));
    ReadOrRefuse(d / "ct", "DICOM slice with sequences, mutant " + std::to_string(i), refused);
  }
  EXPECT_GT(refused, 0);
}

// A zlib-compressed MetaImage: mutants of the header and of the stream (a cut or changed stream
// must be refused, not read as part of a CT and zeros).
TEST(InputMutations, CompressedMetaImage) {
  const std::string voxels = Voxels();
  uLongf size = compressBound(uLong(voxels.size()));
  std::string z(size, '\0');
  compress2(reinterpret_cast<Bytef*>(z.data()), &size,
            reinterpret_cast<const Bytef*>(voxels.data()), uLong(voxels.size()), 9);
  z.resize(size);
  const std::string header = "ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = "
                             "MET_SHORT\nElementSpacing = 1 1 1\nCompressedData = True\n"
                             "CompressedDataSize = " +
                             std::to_string(z.size()) + "\nElementDataFile = LOCAL\n";
  FuzzFile("z.mha", header + z, header.size() + z.size(), 400, 6);
}
