// bmsim - the BoneMachining command line. Subcommands register themselves (bmsimCommand.h); CLI11
// parses their options and writes every --help (Docs/CommandLine.md). Exit status: 0 success,
// 1 an error while running, 2 bad command-line use (the message names the option).
#include "bmsimArgs.h"
#include "bmsimCommand.h"

#include "bmResources.h"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <exception>
#include <iostream>
#include <memory>

#ifdef BM_WITH_OPENCL
#include "bmOpenCLBackend.h"
#endif

namespace bm::cli {
std::map<std::string, Command>& Registry() {
  static std::map<std::string, Command> r;
  return r;
}
} // namespace bm::cli

namespace {

/// Whether `s` is well-formed UTF-8 (no overlong forms, surrogates or values above U+10FFFF).
bool IsUtf8(const char* s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s);
  while (*p) {
    const unsigned char c = *p;
    int extra = 0;
    uint32_t cp = 0;
    if (c < 0x80) {
      ++p;
      continue;
    } else if ((c & 0xe0) == 0xc0) {
      extra = 1;
      cp = c & 0x1f;
    } else if ((c & 0xf0) == 0xe0) {
      extra = 2;
      cp = c & 0x0f;
    } else if ((c & 0xf8) == 0xf0) {
      extra = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    ++p;
    for (int k = 0; k < extra; ++k, ++p) {
      if ((*p & 0xc0) != 0x80)
        return false;
      cp = (cp << 6) | (*p & 0x3f);
    }
    static const uint32_t kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[extra] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff))
      return false;
  }
  return true;
}

} // namespace

int main(int argc, char** argv) {
#ifdef BM_WITH_OPENCL
  bm::RegisterOpenCLBackend();
#endif
  CLI::App app{"bmsim - the BoneMachining command line: bone machining and glenoid reaming "
               "simulation",
               "bmsim"};
  app.set_version_flag("--version", std::string("bmsim (BoneMachining) ") + BM_VERSION +
                                        "\nresources: " + bm::ResourceDir().string());
  app.require_subcommand(1, 1);
  app.footer("'bmsim COMMAND --help' describes a command's options. Exit status: 0 success, 1 "
             "error, 2 bad command-line use.");
  std::map<CLI::App*, std::unique_ptr<bm::cli::ParsedArgs>> options;
  for (const auto& [name, cmd] : bm::cli::Registry()) {
    CLI::App* sub = app.add_subcommand(name, cmd.help);
    auto args = std::make_unique<bm::cli::ParsedArgs>(*sub);
    cmd.declare(*args);
    options[sub] = std::move(args);
  }
  std::string name;
  // Paths and values end up in JSON outputs (summary.json, plan.json), which must be UTF-8: an
  // argument that is not would fail after the work, when its output is written. Said first.
  for (int i = 1; i < argc; ++i)
    if (!IsUtf8(argv[i])) {
      std::cerr << "bmsim: argument " << i
                << " is not valid UTF-8 (a path in another encoding?); its outputs are written as "
                   "UTF-8 JSON: rename the file or folder\n";
      return 2;
    }
  if (argc > 1 && argv[1][0] != '-' && !bm::cli::Registry().count(argv[1])) {
    std::cerr << "bmsim: unknown command '" << argv[1] << "'\n" << app.help();
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    for (const CLI::App* s : app.get_subcommands())
      name = " " + s->get_name();
    std::cerr << "bmsim" << name << ": " << e.what() << "\nRun 'bmsim" << name
              << " --help' for the options.\n";
    return 2;
  }
  CLI::App* sub = app.get_subcommands().at(0);
  name = sub->get_name();
  try {
    return bm::cli::Registry().at(name).fn(*options.at(sub));
  } catch (const bm::cli::UsageError& e) {
    std::cerr << "bmsim " << name << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "bmsim " << name << ": error: " << e.what() << "\n";
    return 1;
  }
}
