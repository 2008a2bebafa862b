#include <malloc.h>

#include "app/cli.h"

int main(int argc, char** argv) {
  // Camera images are large and replaced every frame. glibc would give each its own mapping and
  // return it when freed, so every new image faulted in all its pages again (and page faults
  // serialise threads decoding side by side); kept in the heap, freed images are reused.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  return rt::app::run_cli(argc, argv);
}
