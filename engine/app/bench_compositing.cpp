// The command line of bench compositing; the work itself is pipeline/jobs/bench_compositing.cpp.
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>
#include <vector>

#include "app/bench_command.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

std::unique_ptr<Command> make_bench_compositing_command() {
  class BenchCompositing : public BenchCommand {
   public:
    BenchCompositing()
        : BenchCommand("compositing",
                       "Per-pass GPU ms of the compositing passes and the bandwidth each achieves, next to a plain "
                       "copy pass in the same run (the roofline); OUT/bench_compositing.json",
                       "Frames per size (median over them)", "1280x720 and 2560x1440") {}
    int run() override { return run_bench_compositing(options_); }
  };
  return std::make_unique<BenchCompositing>();
}

}  // namespace rt::app
