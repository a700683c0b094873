// bmsimCommand.h - how a `bmsim` subcommand joins the command line.
//
// Each subcommand lives in its own file (bmsimRun.cxx, bmsimImport.cxx, ...) and registers itself:
//   BM_REGISTER_COMMAND(run, "run a scene (drilling, glenoid or FILE.json)", RunCommand);
// The function gets the arguments after the subcommand name and returns the process exit code.
// Errors: throw bm::cli::UsageError (exit 2, message + usage) or any std::exception (exit 1,
// message). A command writes its outputs only after all its inputs were checked (nothing half
// written).
#pragma once

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace bm::cli {

using Args = std::vector<std::string>;
using CommandFn = std::function<int(const Args&)>;

struct Command {
  std::string help;
  CommandFn fn;
};

/// Bad command-line use: the message names the problem; bmsim exits with status 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::map<std::string, Command>& Registry();

struct Registrar {
  Registrar(const std::string& name, const std::string& help, CommandFn fn) {
    Registry()[name] = Command{help, std::move(fn)};
  }
};

} // namespace bm::cli

#define BM_REGISTER_COMMAND(name, help, fn)                                                        \
  static ::bm::cli::Registrar bmRegistrar_##name(#name, help, fn)
