// The command line of bench ibr; the work itself is pipeline/jobs/bench_ibr.cpp.
#include <nlohmann/json.hpp>

#include "app/bench_command.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

std::unique_ptr<Command> make_bench_ibr_command() {
  class BenchIbr : public BenchCommand {
   public:
    BenchIbr()
        : BenchCommand("ibr",
                       "Per-pass GPU ms of the image-based model for 2, 4 and 6 views (or --views N) on one frame of "
                       "the clap scene, next to a copy pass; OUT/bench_ibr.json",
                       "Frames per size and view count (median over them)", "640x360, 1280x720 and 2560x1440") {}
    int run() override {
      IbrSettings settings;
      ibr_.apply(settings);
      return run_bench_ibr(options_, settings, ibr_.given("views"));
    }

   protected:
    void add_options(CLI::App& command) override {
      ibr_ = add_ibr_options(command);
      ibr_.option("views")->description("Only this many cameras per frame (default: 2, 4 and 6)")->default_str("");
    }

   private:
    IbrOptions ibr_;
  };
  return std::make_unique<BenchIbr>();
}

}  // namespace rt::app
