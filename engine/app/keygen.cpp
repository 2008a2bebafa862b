// `remotetouch keygen FILE`: a new session key for two sites (the same file at both), written so
// that only its owner can read it and never over an existing file.
#include <iostream>

#include "app/command.h"
#include "net/secure_channel.h"

namespace rt::app {
namespace {

class KeygenCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command = parent.add_subcommand("keygen", "Make a session key file (mode 0600; never overwrites one)");
    command->add_option("file", file_, "Where to write the key (copy it to the other site over a trusted channel)")->required();
    return command;
  }
  int run() override {
    net::write_new_session_key_file(file_);
    std::cout << "wrote a new session key to " << file_.string() << " (mode 0600)\n";
    return 0;
  }

 private:
  std::filesystem::path file_;
};

}  // namespace

std::unique_ptr<Command> make_keygen_command() { return std::make_unique<KeygenCommand>(); }

}  // namespace rt::app
