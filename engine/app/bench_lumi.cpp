// The command line of bench lumi; the work itself is pipeline/jobs/bench_lumi.cpp.
#include "app/bench_command.h"
#include "config/assets.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

std::unique_ptr<Command> make_bench_lumi_command() {
  class BenchLumi : public BenchCommand {
   public:
    BenchLumi()
        : BenchCommand("lumi",
                       "Lumi-Net's GPU kernels against OpenCV DNN running its ONNX export on the same tensors and CPU, "
                       "and the lumigraph blending for scale, on one frame of the clap scene (4 views); "
                       "OUT/bench_lumi.json",
                       "Frames to time (median over them)", "640x360") {}
    int run() override {
      IbrSettings settings;
      ibr_.apply(settings);
      if (options_.width == 0) {
        options_.width = 640;
        options_.height = 360;
      }
      return run_bench_lumi(options_, settings, onnx_);
    }

   protected:
    void add_options(CLI::App& command) override {
      // Four views: the ONNX export's; both blendings run.
      ibr_ = add_ibr_options(command, {"views", "blend"});
      onnx_ = (config::assets_dir() / "lumi" / "lumi_net.onnx").string();
      command.add_option("--onnx", onnx_, "The network's ONNX export, for OpenCV DNN (that of --lumi-weights)")
          ->check(CLI::ExistingFile)
          ->capture_default_str();
    }

   private:
    IbrOptions ibr_;
    std::string onnx_;
  };
  return std::make_unique<BenchLumi>();
}

}  // namespace rt::app
