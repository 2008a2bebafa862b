#include "app/cli.h"

int main(int argc, char** argv) { return rt::app::run_cli(argc, argv); }
