#pragma once
// The hand template (paper section 3.1.2): a skinned triangle mesh of a left or a right hand in
// its rest pose (flat, palm towards +z, fingers along +y, wrist at the origin, metres) with its
// forearm (down -y to the elbow), its bones in the tracker's hierarchy, and a UV-mapped skin
// texture (back of the hand and forearm in the left half, palm side in the right half, nails on
// the back). Stored as glTF 2.0 under assets/hand/ and generated from the simulator's skeleton
// definition (sim/hand_model.h) by make_hand_template. The glTF mesh's extras carry
// hand_index_count, palm_width_m and arm_width_m.
#include <array>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "hand/hand_bones.h"
#include "image/host_image.h"

namespace rt::hand {

using shader_abi::HandVertex;

struct HandTemplate {
  bool is_left = false;
  std::vector<HandVertex> vertices;  // at most four influences, weights summing to one
  std::vector<uint32_t> indices;     // triangle list: the hand's triangles, then the forearm's
  uint32_t hand_index_count = 0;     // indices[0, hand_index_count) draw the hand alone
  double palm_width_m = 0.0;         // the width a tracker reports for this hand (shape adaption's reference)
  double arm_width_m = 0.0;          // the forearm's width (diameter)
  RestSkeleton rest{};               // B_j and the bone lengths
  HostImage texture;                 // RGBA32F linear RGB albedo, alpha 1 (the PNG is sRGB, as glTF says)
};

class HandTemplateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::filesystem::path hand_template_file(const std::filesystem::path& dir, bool is_left);  // dir/{left,right}_hand.gltf
// Throws HandTemplateError naming the file and what is wrong with it.
HandTemplate load_hand_template(const std::filesystem::path& gltf_file);
HandTemplate load_hand_template(const std::filesystem::path& dir, bool is_left);
// Checks the invariants load_hand_template promises; throws HandTemplateError.
void validate_hand_template(const HandTemplate& hand, const std::string& where);

// The generator: the template built from sim::medium_adult_hand() at hand_scale 1.
HandTemplate build_hand_template(bool is_left);
HostImage build_skin_texture(uint32_t size);
// Writes dir/{left,right}_hand.gltf and .bin, and dir/texture_name (PNG) when the hand carries
// a texture.
void write_hand_template(const HandTemplate& hand, const std::filesystem::path& dir, const std::string& texture_name);

}  // namespace rt::hand
