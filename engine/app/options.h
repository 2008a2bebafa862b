#pragma once
// What every subcommand takes from the command line.
#include <string>

#include "pipeline/run_options.h"

namespace rt::app {

using pipeline::RunOptions;

int run_compose(const RunOptions& options);
int run_bench(const std::string& what, const RunOptions& options);

}  // namespace rt::app
