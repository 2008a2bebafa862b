#pragma once
// `remotetouch eval hand` (eval_hand.cpp): measures the geometry hand (skinning accuracy,
// fingertip error before and after shape adaption, color difference before and after appearance
// adaption) on synthetic users; `remotetouch bench hand` (bench_hand.cpp): GPU ms of skinning and
// rasterization.
#include "app/options.h"

namespace rt::app {

int run_bench_hand(const RunOptions& options);

}  // namespace rt::app
