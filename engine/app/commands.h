#pragma once
// The one list of the command line's commands (commands.cpp).
#include <memory>
#include <string>
#include <vector>

#include "app/command.h"

namespace rt::app {

struct ListedCommand {
  std::string parent;  // "" for a top-level command, else "bench", "eval" or "calibrate"
  std::unique_ptr<Command> command;
};

// A parent with no action of its own: it takes one of its commands.
struct CommandGroup {
  std::string name, description;
};

// Every command, in the order `remotetouch --help` lists them.
std::vector<ListedCommand> make_commands();
const std::vector<CommandGroup>& command_groups();

}  // namespace rt::app
