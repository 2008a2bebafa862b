#pragma once
// Runs the Catch2 session with the command line; defined beside Catch2's implementation
// (support/catch_impl.cpp), which is compiled once for both halves' mains.
namespace rt::test {

int run_catch_session(int argc, char** argv);

}  // namespace rt::test
