#pragma once
// The plots of a command are drawn by a Python script under scripts/ with Debian's
// python3-matplotlib (scripts/packages.txt): one way to find and run them.
#include <filesystem>
#include <string>

namespace rt::pipeline {

// Runs scripts/`script` on `dir` with /usr/bin/python3 (else python3 on the PATH). Throws
// std::runtime_error naming `command`, the command line, what it needs and `already_written`.
void run_plot_script(const std::string& script, const std::filesystem::path& dir, const std::string& command,
                     const std::string& already_written);

}  // namespace rt::pipeline
