// The test main of the CPU half: Catch2 alone, no GPU context to destroy or validate.
#include "support/catch_session.h"

int main(int argc, char** argv) { return rt::test::run_catch_session(argc, argv); }
