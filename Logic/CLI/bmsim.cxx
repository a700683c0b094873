// bmsim - the BoneMachining command line. Subcommands register themselves (bmsimCommand.h).
#include "bmsimCommand.h"

#include "bmResources.h"

#include <exception>
#include <iostream>

#ifdef BM_WITH_OPENCL
#include "bmOpenCLBackend.h"
#endif

namespace bm::cli {
std::map<std::string, Command>& Registry() {
  static std::map<std::string, Command> r;
  return r;
}
} // namespace bm::cli

static void PrintUsage(std::ostream& os) {
  os << "usage: bmsim COMMAND [options]\n\ncommands:\n";
  for (const auto& [name, cmd] : bm::cli::Registry())
    os << "  " << name << "\t" << cmd.help << "\n";
  os << "\n'bmsim COMMAND --help' describes a command's options; 'bmsim --version' prints the\n"
        "version and the resource folder in use.\n";
}

int main(int argc, char** argv) {
#ifdef BM_WITH_OPENCL
  bm::RegisterOpenCLBackend();
#endif
  if (argc < 2) {
    PrintUsage(std::cerr);
    return 2;
  }
  std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    PrintUsage(std::cout);
    return 0;
  }
  if (name == "--version") {
    std::cout << "bmsim (BoneMachining) " << BM_VERSION << "\nresources: " << bm::ResourceDir().string()
              << "\n";
    return 0;
  }
  auto it = bm::cli::Registry().find(name);
  if (it == bm::cli::Registry().end()) {
    std::cerr << "bmsim: unknown command '" << name << "'\n";
    PrintUsage(std::cerr);
    return 2;
  }
  try {
    return it->second.fn(bm::cli::Args(argv + 2, argv + argc));
  } catch (const bm::cli::UsageError& e) {
    std::cerr << "bmsim " << name << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "bmsim " << name << ": error: " << e.what() << "\n";
    return 1;
  }
}
