#pragma once
// What every subcommand takes from the command line.
#include <string>

#include "pipeline/run_options.h"

namespace rt::app {

using pipeline::RunOptions;

}  // namespace rt::app
