// Catch2's implementation, compiled once for both halves' mains (it is the slowest unit the
// tests have); each main only runs the session.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "support/catch_session.h"

namespace rt::test {

int run_catch_session(int argc, char** argv) { return Catch::Session().run(argc, argv); }

}  // namespace rt::test
