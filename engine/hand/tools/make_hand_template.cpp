// make_hand_template DIR: writes the left and right hand templates (glTF 2.0, .bin, skin PNG)
// generated from the simulator's skeleton definition into DIR (normally assets/hand/).
#include <exception>
#include <iostream>

#include "hand/hand_template.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_hand_template OUTPUT_DIR\n";
    return 2;
  }
  try {
    for (bool is_left : {false, true}) {
      const rt::hand::HandTemplate hand = rt::hand::build_hand_template(is_left);
      rt::hand::write_hand_template(hand, argv[1], "hand_skin.png");
      // Read back what was written: the files must load as the receiver will load them.
      const rt::hand::HandTemplate loaded = rt::hand::load_hand_template(argv[1], is_left);
      std::cout << rt::hand::hand_template_file(argv[1], is_left).string() << ": " << loaded.vertices.size()
                << " vertices, " << loaded.indices.size() / 3 << " triangles\n";
    }
  } catch (const std::exception& error) {
    std::cerr << "make_hand_template: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
