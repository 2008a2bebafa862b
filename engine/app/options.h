#pragma once
// What every subcommand takes from the command line.
#include <cstdint>
#include <filesystem>
#include <string>

namespace rt::app {

struct RunOptions {
  std::filesystem::path out;
  uint32_t frames = 1;
  std::string device;       // substring of the Vulkan device name; empty = automatic
  bool profile = false;     // print per-pass GPU times (median over frames)
  int capture_frame = -1;   // RenderDoc capture of this frame (0-based); -1 = none
  bool validation = false;  // Khronos validation layer on
  uint32_t width = 0;
  uint32_t height = 0;
  bool dump_passes = false;  // write every pass output of the last frame as EXR and PNG
};

int run_compose(const RunOptions& options);
int run_bench(const std::string& what, const RunOptions& options);

}  // namespace rt::app
