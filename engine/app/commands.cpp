// The one list of commands: a new subcommand is one new file (a Command and its
// make_NAME_command()) plus one line here.
#include "app/commands.h"

namespace rt::app {

// X(parent, name): parent "" is the application; each name has a make_<name>_command() in its file.
#define RT_COMMANDS(X)                     \
  X("", demo)                              \
  X("", site)                              \
  X("", compose)                           \
  X("bench", bench_compositing)            \
  X("bench", bench_lumi)                   \
  X("bench", bench_touch)                  \
  X("bench", bench_camera)                 \
  X("bench", bench_simulate)               \
  X("bench", bench_ibr)                    \
  X("bench", bench_hand)                   \
  X("bench", bench_net)                    \
  X("bench", bench_webrtc)                 \
  X("bench", bench_accuracy)               \
  X("", simulate)                          \
  X("", keygen)                            \
  X("", inspect_camera)                    \
  X("", list_cameras)                      \
  X("", record)                            \
  X("eval", eval_ibr)                      \
  X("eval", eval_hand)                     \
  X("eval", eval_dual)                     \
  X("export", export_lumi)                 \
  X("calibrate", calibrate_intrinsics)     \
  X("calibrate", calibrate_extrinsics)     \
  X("calibrate", calibrate_tracker)        \
  X("calibrate", calibrate_synthesize)

#define RT_DECLARE_COMMAND(parent, name) std::unique_ptr<Command> make_##name##_command();
RT_COMMANDS(RT_DECLARE_COMMAND)
#undef RT_DECLARE_COMMAND

std::vector<ListedCommand> make_commands() {
  std::vector<ListedCommand> list;
#define RT_LIST_COMMAND(parent, name) list.push_back({parent, make_##name##_command()});
  RT_COMMANDS(RT_LIST_COMMAND)
#undef RT_LIST_COMMAND
  return list;
}

const std::vector<CommandGroup>& command_groups() {
  static const std::vector<CommandGroup> groups = {
      {"bench", "Benchmarks: per-pass GPU times, latency, bandwidth (one command per benchmark)"},
      {"eval", "Measure a part of the system against the simulator's ground truth"},
      {"export", "Training data from the simulator (Lumi-Net's: scripts/train-lumi)"},
      {"calibrate", "Calibrate a site: camera intrinsics, camera poses, the hand tracker"},
  };
  return groups;
}

}  // namespace rt::app
