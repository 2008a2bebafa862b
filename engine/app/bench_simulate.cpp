// The command line of bench simulate; the work itself is pipeline/jobs/bench_simulate.cpp.

#include "app/bench_command.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

std::unique_ptr<Command> make_bench_simulate_command() {
  class BenchSimulate : public BenchCommand {
   public:
    BenchSimulate()
        : BenchCommand("simulate",
                       "One frame of all six simulated RGBD cameras at full resolution: wall ms per frame and GPU ms "
                       "per pass",
                       "Frames to time (median over them)") {}
    int run() override {
      return run_bench_simulate(options_);
    }
  };
  return std::make_unique<BenchSimulate>();
}

}  // namespace rt::app
