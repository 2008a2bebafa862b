// The command line of bench hand; the work itself is pipeline/jobs/bench_hand.cpp.
#include <nlohmann/json.hpp>

#include "app/bench_command.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

std::unique_ptr<Command> make_bench_hand_command() {
  class BenchHand : public BenchCommand {
   public:
    BenchHand()
        : BenchCommand("hand",
                       "GPU ms of the geometry hand's passes (skinning, rasterization, appearance adaption), next to a "
                       "copy pass; OUT/bench_hand.json",
                       "Frames per size (median over them)", "1280x720 and 2560x1440") {}
    int run() override { return run_bench_hand(options_); }
  };
  return std::make_unique<BenchHand>();
}

}  // namespace rt::app
