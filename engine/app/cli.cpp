#include "app/cli.h"

#include <CLI/CLI.hpp>
#include <iostream>
#include <map>

#include "app/commands.h"

namespace rt::app {

int run_cli(int argc, char** argv) {
  CLI::App app{"RemoteTouch: two people clap hands through their screens (Vulkan engine)", "remotetouch"};
  app.require_subcommand(1);

  // The commands in the list's order; a group (bench, eval, calibrate) where its first command is.
  std::map<std::string, CLI::App*> parents = {{"", &app}};
  std::vector<ListedCommand> commands = make_commands();
  std::vector<std::pair<CLI::App*, Command*>> added;
  for (ListedCommand& listed : commands) {
    if (!parents.count(listed.parent))
      for (const CommandGroup& group : command_groups())
        if (group.name == listed.parent) {
          // Not require_subcommand: then `bench nonsense` would say only that a subcommand is
          // required, not that "nonsense" is none; a group left without one is refused below.
          parents[group.name] = app.add_subcommand(group.name, group.description);
        }
    added.push_back({listed.command->add_to(*parents.at(listed.parent)), listed.command.get()});
  }

  Command* chosen = nullptr;
  try {
    app.parse(argc, argv);
    for (const auto& [subcommand, command] : added)
      if (subcommand->parsed()) chosen = command;
    for (const CommandGroup& group : command_groups())
      if (!chosen && parents.count(group.name) && parents.at(group.name)->parsed())
        throw CLI::RequiredError("remotetouch " + group.name + ": a subcommand (see remotetouch " + group.name +
                                 " --help)");
    if (chosen) chosen->check();
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  }
  if (!chosen) return 1;
  try {
    return chosen->run();
  } catch (const std::exception& error) {
    std::cerr << "remotetouch: error: " << error.what() << "\n";
    return 1;
  }
}

}  // namespace rt::app
