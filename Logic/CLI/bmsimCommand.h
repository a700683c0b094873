// bmsimCommand.h - how a `bmsim` subcommand joins the command line.
//
// Each subcommand lives in its own file (bmsimRun.cxx, bmsimImport.cxx, ...) and registers itself
// with a function that declares its options (bmsimArgs.h, parsed by CLI11, which also writes its
// --help) and one that runs it:
//   BM_REGISTER_COMMAND(run, "run a scene (drilling, glenoid or FILE.json)", RunOptions,
//   RunCommand);
// The run function gets the parsed options and returns the process exit code. Errors: a bad
// option or value is refused by the parser (exit 2, the message names the option and its range);
// a command throws bm::cli::UsageError for a bad combination (exit 2) or any std::exception
// (exit 1, message). A command writes its outputs only after all its inputs were checked
// (nothing half written). Docs/CommandLine.md lists every command.
#pragma once

#include <functional>
#include <map>
#include <stdexcept>
#include <string>

namespace bm::cli {

class ParsedArgs; // bmsimArgs.h

using DeclareFn = std::function<void(ParsedArgs&)>;
using CommandFn = std::function<int(const ParsedArgs&)>;

struct Command {
  std::string help;
  DeclareFn declare;
  CommandFn fn;
};

/// Bad command-line use: the message names the problem; bmsim exits with status 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::map<std::string, Command>& Registry();

struct Registrar {
  Registrar(const std::string& name, const std::string& help, DeclareFn declare, CommandFn fn) {
    Registry()[name] = Command{help, std::move(declare), std::move(fn)};
  }
};

} // namespace bm::cli

#define BM_REGISTER_COMMAND(name, help, declare, fn)                                               \
  static ::bm::cli::Registrar bmRegistrar_##name(#name, help, declare, fn)
