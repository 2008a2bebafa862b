#include "pipeline/plot_script.h"

#include <cstdlib>
#include <stdexcept>

#include "config/assets.h"

namespace rt::pipeline {

void run_plot_script(const std::string& script, const std::filesystem::path& dir, const std::string& command,
                     const std::string& already_written) {
  const std::filesystem::path path = config::scripts_dir() / script;
  if (!std::filesystem::exists(path)) throw std::runtime_error(command + ": the plotting script " + path.string() + " is missing");
  // Debian's interpreter, where python3-matplotlib is installed, before any other on the PATH.
  const std::string python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  auto quoted = [](const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
  };
  const std::string line = python + " " + quoted(path.string()) + " " + quoted(dir.string());
  if (std::system(line.c_str()) != 0)
    throw std::runtime_error(command + ": plotting failed (" + line +
                             "); it needs Debian's python3-matplotlib (scripts/packages.txt). " + already_written);
}

}  // namespace rt::pipeline
