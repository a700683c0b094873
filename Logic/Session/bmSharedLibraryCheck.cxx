#include "bmSharedLibraryCheck.h"

#include <dlfcn.h>
#include <elf.h>
#include <link.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace bm {

namespace {

#if defined(__x86_64__)
constexpr uint16_t kMachine = EM_X86_64;
constexpr const char* kMultiarch = "x86_64-linux-gnu";
#elif defined(__aarch64__)
constexpr uint16_t kMachine = EM_AARCH64;
constexpr const char* kMultiarch = "aarch64-linux-gnu";
#else
#error "bmSharedLibraryCheck: add this machine's ELF machine code"
#endif

bool IsRegularFile(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

[[noreturn]] void Refuse(const std::string& path, const std::string& why) {
  throw std::runtime_error("'" + path + "' is not a usable shared library: " + why);
}

// offset + count * size <= fileSize, without overflow.
bool Fits(uint64_t offset, uint64_t count, uint64_t size, uint64_t fileSize) {
  if (offset > fileSize)
    return false;
  if (size != 0 && count > (fileSize - offset) / size)
    return false;
  return true;
}

} // namespace

std::string FindSharedLibrary(const std::string& name) {
  if (name.find('/') != std::string::npos)
    return name;
  std::vector<std::string> folders;
  if (const char* env = std::getenv("LD_LIBRARY_PATH")) {
    std::stringstream list(env);
    std::string folder;
    while (std::getline(list, folder, ':'))
      folders.push_back(folder.empty() ? "." : folder);
  }
  for (std::string folder :
       {std::string("/usr/local/lib"), std::string("/usr/lib/") + kMultiarch,
        std::string("/usr/lib"), std::string("/lib/") + kMultiarch, std::string("/lib")})
    folders.push_back(folder);
  for (const std::string& folder : folders) {
    const std::string path = folder + "/" + name;
    if (IsRegularFile(path))
      return path;
  }
  return {};
}

void CheckSharedLibraryFile(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0)
    Refuse(path, std::string("cannot be read (") + std::strerror(errno) + ")");
  if (!S_ISREG(st.st_mode))
    Refuse(path, "not a regular file");
  const uint64_t fileSize = uint64_t(st.st_size);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    Refuse(path, "cannot be opened");
  Elf64_Ehdr eh{};
  in.read(reinterpret_cast<char*>(&eh), sizeof(eh));
  if (in.gcount() < SELFMAG || std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0)
    Refuse(path, "not an ELF file");
  if (fileSize < sizeof(eh) || in.gcount() != std::streamsize(sizeof(eh)))
    Refuse(path, "truncated: too short for an ELF header (" + std::to_string(fileSize) + " bytes)");
  if (eh.e_ident[EI_CLASS] != ELFCLASS64)
    Refuse(path, "not a 64-bit ELF object");
  if (eh.e_ident[EI_DATA] != ELFDATA2LSB)
    Refuse(path, "not little-endian");
  if (eh.e_machine != kMachine)
    Refuse(path, "built for another machine (ELF machine " + std::to_string(eh.e_machine) + ")");
  if (eh.e_type != ET_DYN)
    Refuse(path, "not a shared object (ELF type " + std::to_string(eh.e_type) + ")");
  if (eh.e_phentsize != sizeof(Elf64_Phdr) || eh.e_phnum == 0)
    Refuse(path, "no valid program header table");
  if (!Fits(eh.e_phoff, eh.e_phnum, eh.e_phentsize, fileSize))
    Refuse(path, "truncated: its program header table ends past the end of the file (" +
                     std::to_string(fileSize) + " bytes)");
  if (eh.e_shoff != 0 && !Fits(eh.e_shoff, eh.e_shnum, eh.e_shentsize, fileSize))
    Refuse(path, "truncated: its section header table ends past the end of the file (" +
                     std::to_string(fileSize) + " bytes)");
  std::vector<Elf64_Phdr> ph(eh.e_phnum);
  in.seekg(std::streamoff(eh.e_phoff));
  if (!in.read(reinterpret_cast<char*>(ph.data()), std::streamsize(ph.size() * sizeof(Elf64_Phdr))))
    Refuse(path, "its program header table cannot be read");
  bool loadable = false;
  for (const Elf64_Phdr& p : ph) {
    if (p.p_type == PT_LOAD)
      loadable = true;
    if (p.p_type != PT_NULL && !Fits(p.p_offset, 1, p.p_filesz, fileSize))
      Refuse(path, "truncated: a segment's bytes end at " +
                       std::to_string(p.p_offset + p.p_filesz) + ", past the end of the file (" +
                       std::to_string(fileSize) + " bytes)");
  }
  if (!loadable)
    Refuse(path, "no loadable segment");
}

void* BindLibraryFunction(void* handle, const char* name, const std::string& path) {
  dlerror();
  void* sym = dlsym(handle, name);
  if (!sym)
    throw std::runtime_error("'" + path + "' has no symbol " + name);
  Dl_info info{};
  void* entryAddress = nullptr;
  if (!dladdr1(sym, &info, &entryAddress, RTLD_DL_SYMENT) || !entryAddress)
    throw std::runtime_error("'" + path + "': symbol " + name + " lies in no loaded object");
  const auto* entry = static_cast<const ElfW(Sym)*>(entryAddress);
  const unsigned type = ELF64_ST_TYPE(entry->st_info);
  if (type != STT_FUNC && type != STT_GNU_IFUNC)
    throw std::runtime_error("'" + path + "': symbol " + name + " is not a function (ELF type " +
                             std::to_string(type) + ")");
  struct link_map* own = nullptr;
  void* definer = nullptr;
  Dl_info again{};
  if (dlinfo(handle, RTLD_DI_LINKMAP, &own) != 0 ||
      !dladdr1(sym, &again, &definer, RTLD_DL_LINKMAP) || definer != static_cast<void*>(own))
    throw std::runtime_error("'" + path + "' does not define " + name + " itself (it comes from '" +
                             (info.dli_fname ? info.dli_fname : "?") + "')");
  return sym;
}

} // namespace bm
