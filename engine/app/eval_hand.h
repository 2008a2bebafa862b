#pragma once
// `remotetouch eval hand`: measures the geometry hand (skinning accuracy, fingertip error before
// and after shape adaption, color difference before and after appearance adaption) on
// synthetic users, and `remotetouch bench hand`: GPU ms of skinning and rasterization.
#include <CLI/CLI.hpp>

#include "app/options.h"

namespace rt::app {

class EvalHandCommand {
 public:
  explicit EvalHandCommand(CLI::App& eval);  // registers `hand` under `eval`
  bool parsed() const { return command_->parsed(); }
  int run() const;

 private:
  CLI::App* command_;
  RunOptions options_;
};

int run_bench_hand(const RunOptions& options);

}  // namespace rt::app
