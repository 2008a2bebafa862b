#pragma once
// One command of the command line (`remotetouch demo`, `remotetouch bench ibr`, ...): it adds its
// subcommand and options to a parent, checks what the options say together once parsed, and
// runs. Each command is one file; app/commands.cpp is the one list of them.
#include <CLI/CLI.hpp>

#include <memory>

namespace rt::app {

class Command {
 public:
  virtual ~Command() = default;
  // Adds the subcommand with its options under `parent` (the application, or `bench`, `eval`,
  // `calibrate`); returns it.
  virtual CLI::App* add_to(CLI::App& parent) = 0;
  // After parsing, when this command was chosen: checks that need several options (throws
  // CLI::ValidationError, reported like a parse error).
  virtual void check() {}
  // Runs the command; returns the exit code. Errors are thrown.
  virtual int run() = 0;
};

}  // namespace rt::app
