#pragma once
// What a run of the engine takes from its caller: where to write, which device, how many frames,
// and the inspection switches (profile, capture, pass dumps).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rt::pipeline {

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
  // A window on the device's screen: the instance extensions its surface needs, and a device that
  // can present (vk::ContextOptions).
  std::vector<std::string> surface_instance_extensions;
  bool presentation = false;
};

}  // namespace rt::pipeline
