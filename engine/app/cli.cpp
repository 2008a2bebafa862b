#include "app/cli.h"

#include <CLI/CLI.hpp>
#include <iostream>
#include <algorithm>
#include <iterator>
#include <map>
#include <sstream>

#include "app/commands.h"
#include "app/suggestion.h"

namespace rt::app {
namespace {

// The subcommand the user got to: the one CLI11 was parsing when it met the unexpected words.
const CLI::App* deepest_parsed(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands())
    if (sub->parsed()) return deepest_parsed(*sub);
  return &app;
}

std::string command_path(const CLI::App* app) {
  std::string path;
  for (; app; app = app->get_parent()) path = app->get_name() + (path.empty() ? "" : " " + path);
  return path;
}

// CLI11 says only which words it did not expect: name the nearest option or command for each.
int report_unexpected(const CLI::App& app, const CLI::ExtrasError& error) {
  const CLI::App* command = deepest_parsed(app);
  const std::string path = command_path(command);
  std::vector<std::string> options, subcommands;
  for (const CLI::Option* option : command->get_options()) {
    if (option->get_group().empty()) continue;  // hidden
    for (const std::string& name : option->get_lnames()) options.push_back("--" + name);
  }
  for (const CLI::App* sub : command->get_subcommands([](const CLI::App*) { return true; }))
    subcommands.push_back(sub->get_name());
  const std::string what = error.what();
  const size_t colon = what.find(": ");
  std::istringstream stream(colon == std::string::npos ? std::string() : what.substr(colon + 2));
  // CLI11 lists them last first.
  std::vector<std::string> words{std::istream_iterator<std::string>(stream), std::istream_iterator<std::string>()};
  std::reverse(words.begin(), words.end());
  bool named = false;
  for (const std::string& word : words) {
    const bool option = word.rfind("-", 0) == 0;
    if (!option && named) continue;  // a stray option's value, not worth a line of its own
    const std::string stem = option ? word.substr(0, word.find('=')) : word;
    const std::string nearest = nearest_choice(stem, option ? options : subcommands);
    std::cerr << path << ": unknown " << (option ? "option " : subcommands.empty() ? "argument " : "command ") << stem
              << (nearest.empty() ? "" : "; did you mean " + nearest + "?") << "\n";
    named = true;
  }
  if (!named) std::cerr << path << ": " << what << "\n";
  std::cerr << "Run " << path << " --help for what it takes.\n";
  return error.get_exit_code();
}

}  // namespace

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

  // A mistyped command is "a subcommand is required" to CLI11: name the nearest one instead.
  if (argc > 1 && argv[1][0] != '-') {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(sub->get_name());
    if (std::find(names.begin(), names.end(), argv[1]) == names.end()) {
      const std::string nearest = nearest_choice(argv[1], names);
      std::cerr << "remotetouch: unknown command " << argv[1] << (nearest.empty() ? "" : "; did you mean " + nearest + "?")
                << "\nRun remotetouch --help for the commands.\n";
      return int(CLI::ExitCodes::ExtrasError);
    }
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
  } catch (const CLI::ExtrasError& error) {
    return report_unexpected(app, error);
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
