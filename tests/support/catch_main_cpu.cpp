// The test main of the CPU half: plain Catch2, no GPU context to destroy or validate.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
