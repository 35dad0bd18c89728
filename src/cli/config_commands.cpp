// uavip config --list: the scenario reference generated from the parameter tables
// (app::configReference; scenarios/README.md holds the same text, checked by ctest).

#include <iostream>
#include <memory>

#include "src/cli/commands.h"
#include "uavip/app/scenario.h"

namespace uavip::cli {

void addConfigCommands(CLI::App& cli, CommandRegistry& registry) {
  struct Args {
    bool list{false};
    bool keys{false};
  };
  auto a = std::make_shared<Args>();
  CLI::App* config = cli.add_subcommand(
      "config", "The config keys: every section's keys with default, unit, bounds, layers, help");
  config->add_flag("--list", a->list, "Print the reference as Markdown tables (the default)");
  config->add_flag("--keys", a->keys, "Print one section.key a line");
  registry.add(config, [a] {
    std::cout << app::configReference(a->keys);
    return kExitOk;
  });
}

}  // namespace uavip::cli
