// uavip command line: parses, dispatches to the subcommand files, and turns errors
// into one line and an exit code (docs/ARCHITECTURE.md, "CLI contract"; src/cli/commands.h).

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <new>
#include <set>
#include <string>

#include "src/cli/commands.h"
#include "uavip/core/error.h"
#include "uavip/core/memory.h"
#include "uavip/core/text.h"
#include "uavip/io/cloud_io.h"

#ifndef UAVIP_VERSION
#define UAVIP_VERSION "dev"
#endif

namespace uavip::cli {

bool Verbosity::showProgress() const { return !quiet && (verbose || ::isatty(STDERR_FILENO)); }

app::Progress progressPrinter(const Verbosity& v) {
  if (!v.showProgress()) return {};
  return [](const std::string& msg) { std::cerr << "uavip: " << msg << "\n"; };
}

CLI::App* addMissionCommand(CLI::App& cli, const std::string& name, const std::string& description,
                            std::string& mission) {
  CLI::App* sub = cli.add_subcommand(name, description);
  sub->add_option("mission", mission, "OUT/mission.json written by run or plan")->required();
  return sub;
}

int CommandRegistry::dispatch() const {
  for (const auto& [sub, action] : commands_) {
    if (sub->parsed()) return action();
  }
  return kExitBadInput;
}

}  // namespace uavip::cli

namespace {

/// The CLI: parses the command line and runs the command; every error it can report
/// becomes one line and an exit code (src/cli/commands.h).
int runUavip(int argc, char** argv) {
  // core/memory.h: page faults, not work, were a fifth of stages 1-2.
  uavip::keepFreedMemoryForReuse();
  using namespace uavip::cli;
  CLI::App cli{
      "uavip " UAVIP_VERSION
      ": laser scans of a structure -> a collision-free UAV inspection mission\n"
      "(Phung et al., 'Automatic Interpretation of Unordered Point Cloud Data for UAV Navigation\n"
      "in Construction'). Exit codes: 0 done, 2 bad input, 3 no mission for the chosen surface."};
  cli.set_version_flag("--version", "uavip " UAVIP_VERSION);
  cli.require_subcommand(1);
  cli.fallthrough();  // -q/-v also after the subcommand
  Verbosity v;
  cli.add_flag("-q,--quiet", v.quiet, "Print nothing but errors");
  cli.add_flag("-v,--verbose", v.verbose, "Show progress even when stderr is not a terminal");
  std::string max_memory;
  cli.add_option("--max-memory", max_memory,
                 "Refuse inputs whose estimated memory exceeds this (e.g. 4G, 512M; default 80 % "
                 "of the available memory or the cgroup's limit, whichever is lower)");

  CommandRegistry registry(v);
  addPipelineCommands(cli, registry);
  addValidateCommands(cli, registry);
  addBenchCommands(cli, registry);
  addExportCommands(cli, registry);
  addScanCommands(cli, registry);
  addViewCommands(cli, registry);
  addTileCommands(cli, registry);
  addConfigCommands(cli, registry);
  addPhotoCommands(cli, registry);

  try {
    cli.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return cli.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, like every other error (CLI11 prints two). A first word that is no
    // command is named, with the commands there are.
    std::string commands;
    std::set<std::string> names;
    for (const auto* sub : cli.get_subcommands([](const CLI::App*) { return true; })) {
      commands += (commands.empty() ? "" : ", ") + sub->get_name();
      names.insert(sub->get_name());
    }
    for (int i = 1; i < argc; ++i) {
      const std::string word = argv[i];
      if (word.empty() || word[0] == '-') continue;
      if (names.count(word) == 0) {
        std::cerr << "uavip: error: unknown command '" << uavip::escapeControl(word.substr(0, 60))
                  << "'; the commands are " << commands << " (uavip --help)\n";
        return kExitBadInput;
      }
      break;
    }
    std::string what = e.what();
    for (char& c : what) c = c == '\n' ? ' ' : c;  // CLI11's own line breaks
    std::cerr << "uavip: error: " << uavip::escapeControl(what)
              << " (uavip --help, or uavip COMMAND --help)\n";
    return kExitBadInput;
  }

  try {
    if (v.quiet && v.verbose) throw uavip::InputError("--quiet and --verbose: choose one");
    if (!max_memory.empty())
      uavip::setMemoryBudget(uavip::parseMemorySize(max_memory, "--max-memory"));
    uavip::io::setPclConsole(v.verbose);
    return registry.dispatch();
  } catch (const uavip::InputError& e) {
    std::cerr << "uavip: error: " << uavip::escapeControl(e.what())
              << "\n";  // a file name may hold a newline
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "uavip: error: out of memory: the input is too large for this machine's memory; "
                 "down-sample the "
                 "cloud, raise preprocess.voxel_m or grid.resolution_m, or plan fewer surfaces\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "uavip: internal error: " << uavip::escapeControl(e.what()) << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return runUavip(argc, argv);
  } catch (...) {
    // Only setting up the commands (CLI11, memory) can still throw here.
    std::fputs("uavip: error: the command line could not be set up\n", stderr);
    return 1;
  }
}
