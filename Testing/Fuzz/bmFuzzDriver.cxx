// bmFuzzDriver.cxx - the main() of a fuzz target (bmFuzzTarget.h) in builds without libFuzzer
// (GCC, the sanitizer stages): runs each seed file given, then deterministic mutants of them
// (flipped, replaced, inserted and deleted bytes, cut ends, repeated chunks; a fixed seed, so a
// failure reproduces). A crash or a sanitizer report fails the run; refusals are the target's
// business. With clang and BM_FUZZ=ON the same targets link libFuzzer instead.
//
//   bmfuzz_<name> [--mutations N] [--seed S] FILE_OR_FOLDER...
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bmFuzzTarget.h"

namespace {

std::string ReadAll(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string Mutate(std::string s, std::mt19937_64& rng) {
  const auto pick = [&](size_t n) { return n ? size_t(rng() % n) : 0; };
  const int edits = 1 + int(rng() % 4);
  for (int e = 0; e < edits; ++e) {
    switch (rng() % 7) {
    case 0: // flip a bit
      if (!s.empty())
        s[pick(s.size())] ^= char(1u << (rng() % 8));
      break;
    case 1: { // an interesting byte
      static const char kBytes[] = {'\0', '\n', '[', '{', '"', ',', ':', '-', '9', '\xff', ' '};
      if (!s.empty())
        s[pick(s.size())] = kBytes[pick(sizeof kBytes)];
      break;
    }
    case 2: // insert a byte
      s.insert(s.begin() + std::ptrdiff_t(pick(s.size() + 1)), char(rng() & 0xff));
      break;
    case 3: // delete a run
      if (!s.empty()) {
        const size_t at = pick(s.size());
        s.erase(at, 1 + pick(std::min<size_t>(16, s.size() - at)));
      }
      break;
    case 4: // cut the end
      s.resize(pick(s.size() + 1));
      break;
    case 5: { // repeat a chunk
      if (!s.empty() && s.size() < (1u << 20)) {
        const size_t at = pick(s.size());
        const std::string chunk = s.substr(at, 1 + pick(32));
        s.insert(at, chunk + chunk);
      }
      break;
    }
    default: { // a big or odd number where a digit was
      static const char* kNumbers[] = {"1e308", "-1", "nan", "1e-320", "4096", "99999999999", "0"};
      const size_t at = s.find_first_of("0123456789", pick(s.size()));
      if (at != std::string::npos)
        s.replace(at, 1, kNumbers[pick(7)]);
      break;
    }
    }
  }
  return s;
}

} // namespace

int main(int argc, char** argv) {
  long mutations = 1000;
  unsigned long seed = 1;
  std::vector<std::filesystem::path> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--mutations" && i + 1 < argc)
      mutations = std::atol(argv[++i]);
    else if (a == "--seed" && i + 1 < argc)
      seed = std::strtoul(argv[++i], nullptr, 10);
    else if (std::filesystem::is_directory(a))
      for (const auto& e : std::filesystem::directory_iterator(a))
        inputs.push_back(e.path());
    else
      inputs.emplace_back(a);
  }
  if (inputs.empty() || mutations < 0) {
    std::fprintf(stderr, "usage: %s [--mutations N] [--seed S] FILE_OR_FOLDER...\n", argv[0]);
    return 2;
  }
  std::sort(inputs.begin(), inputs.end());
  std::vector<std::string> seeds;
  for (const auto& p : inputs)
    seeds.push_back(ReadAll(p));
  const auto t0 = std::chrono::steady_clock::now();
  for (const std::string& s : seeds)
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(s.data()), s.size());
  std::mt19937_64 rng(seed);
  for (long m = 0; m < mutations; ++m) {
    const std::string s = Mutate(seeds[size_t(m) % seeds.size()], rng);
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(s.data()), s.size());
  }
  std::printf("%s: %zu seeds and %ld mutants (seed %lu) ran clean in %.2f s\n", argv[0],
              seeds.size(), mutations, seed,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}
