// glTF 2.0 reading and writing of the hand template, through tinygltf.
#include "hand/hand_template.h"

#include <tiny_gltf.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace rt::hand {
namespace {

constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double linear_to_srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

// Appends `bytes` to the buffer (4-byte aligned) and returns a view on them.
int add_view(tinygltf::Model& model, const void* bytes, size_t size, int target) {
  auto& data = model.buffers[0].data;
  while (data.size() % 4) data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = size;
  view.target = target;
  const auto* begin = static_cast<const unsigned char*>(bytes);
  data.insert(data.end(), begin, begin + size);
  model.bufferViews.push_back(view);
  return int(model.bufferViews.size() - 1);
}

int add_accessor(tinygltf::Model& model, int view, int component, int type, size_t count, bool normalized = false) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.componentType = component;
  accessor.type = type;
  accessor.count = count;
  accessor.normalized = normalized;
  model.accessors.push_back(accessor);
  return int(model.accessors.size() - 1);
}

template <typename T>
std::vector<T> gather(const std::vector<HandVertex>& vertices, int components, const float* (*field)(const HandVertex&)) {
  std::vector<T> out;
  for (const HandVertex& v : vertices)
    for (int c = 0; c < components; ++c) out.push_back(T(field(v)[c]));
  return out;
}

}  // namespace

std::filesystem::path hand_template_file(const std::filesystem::path& dir, bool is_left) {
  return dir / (is_left ? "left_hand.gltf" : "right_hand.gltf");
}

void write_hand_template(const HandTemplate& hand, const std::filesystem::path& dir, const std::string& texture_name) {
  validate_hand_template(hand, "the hand template to write");
  const std::filesystem::path file = hand_template_file(dir, hand.is_left);
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "RemoteTouch make_hand_template (engine/hand/hand_template_builder.cpp)";
  model.buffers.resize(1);
  model.buffers[0].uri = file.stem().string() + ".bin";
  const size_t n = hand.vertices.size();

  std::vector<float> positions, normals, uvs;
  std::vector<uint8_t> joints, weights;
  std::vector<double> lo(3, 1e30), hi(3, -1e30);
  for (const HandVertex& v : hand.vertices) {
    for (int c = 0; c < 3; ++c) {
      positions.push_back(v.position_u[c]);
      normals.push_back(v.normal_v[c]);
      lo[c] = std::min(lo[c], double(v.position_u[c]));
      hi[c] = std::max(hi[c], double(v.position_u[c]));
    }
    uvs.push_back(v.position_u[3]);
    uvs.push_back(v.normal_v[3]);
    for (int k = 0; k < 4; ++k) {
      joints.push_back(uint8_t(v.joints[k]));
      weights.push_back(uint8_t(std::lround(std::clamp(v.weights[k], 0.0f, 1.0f) * 255.0f)));
    }
  }
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  const int array = TINYGLTF_TARGET_ARRAY_BUFFER;
  primitive.attributes["POSITION"] =
      add_accessor(model, add_view(model, positions.data(), positions.size() * 4, array), kFloat, TINYGLTF_TYPE_VEC3, n);
  model.accessors.back().minValues = lo;
  model.accessors.back().maxValues = hi;
  primitive.attributes["NORMAL"] =
      add_accessor(model, add_view(model, normals.data(), normals.size() * 4, array), kFloat, TINYGLTF_TYPE_VEC3, n);
  primitive.attributes["TEXCOORD_0"] =
      add_accessor(model, add_view(model, uvs.data(), uvs.size() * 4, array), kFloat, TINYGLTF_TYPE_VEC2, n);
  primitive.attributes["JOINTS_0"] = add_accessor(model, add_view(model, joints.data(), joints.size(), array),
                                                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, n);
  primitive.attributes["WEIGHTS_0"] = add_accessor(model, add_view(model, weights.data(), weights.size(), array),
                                                   TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, n, true);
  if (n <= 65536) {
    std::vector<uint16_t> indices(hand.indices.begin(), hand.indices.end());
    primitive.indices = add_accessor(model, add_view(model, indices.data(), indices.size() * 2, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, indices.size());
  } else {
    primitive.indices = add_accessor(model, add_view(model, hand.indices.data(), hand.indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, hand.indices.size());
  }
  primitive.material = 0;
  tinygltf::Mesh mesh;
  mesh.name = hand.is_left ? "left_hand" : "right_hand";
  mesh.primitives.push_back(primitive);
  mesh.extras = tinygltf::Value(tinygltf::Value::Object{{"hand_index_count", tinygltf::Value(int(hand.hand_index_count))},
                                                        {"palm_width_m", tinygltf::Value(hand.palm_width_m)},
                                                        {"arm_width_m", tinygltf::Value(hand.arm_width_m)}});
  model.meshes.push_back(mesh);

  // Joints: nodes 0..21 in bone order, each with its transform relative to its parent.
  std::vector<float> inverse_bind;
  tinygltf::Skin skin;
  skin.name = mesh.name + "_skin";
  for (int bone = 0; bone < kBoneCount; ++bone) {
    const int parent = bone_parent(bone);
    const Eigen::Isometry3d local =
        parent < 0 ? hand.rest[bone].frame : Eigen::Isometry3d(hand.rest[parent].frame.inverse() * hand.rest[bone].frame);
    tinygltf::Node node;
    node.name = bone_name(bone);
    const Eigen::Quaterniond q(local.linear());
    node.translation = {local.translation().x(), local.translation().y(), local.translation().z()};
    node.rotation = {q.x(), q.y(), q.z(), q.w()};
    node.extras = tinygltf::Value(tinygltf::Value::Object{{"length_m", tinygltf::Value(hand.rest[bone].length_m)}});
    model.nodes.push_back(node);
    if (parent >= 0) model.nodes[parent].children.push_back(bone);
    skin.joints.push_back(bone);
    const Eigen::Matrix4d inverse = hand.rest[bone].frame.inverse().matrix();
    for (int column = 0; column < 4; ++column)
      for (int row = 0; row < 4; ++row) inverse_bind.push_back(float(inverse(row, column)));
  }
  skin.skeleton = kArmBone;
  skin.inverseBindMatrices = add_accessor(model, add_view(model, inverse_bind.data(), inverse_bind.size() * 4, 0), kFloat,
                                          TINYGLTF_TYPE_MAT4, kBoneCount);
  model.skins.push_back(skin);
  tinygltf::Node mesh_node;
  mesh_node.name = mesh.name;
  mesh_node.mesh = 0;
  mesh_node.skin = 0;
  model.nodes.push_back(mesh_node);
  tinygltf::Scene scene;
  scene.nodes = {kArmBone, int(model.nodes.size() - 1)};
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  tinygltf::Material material;
  material.name = "skin";
  material.pbrMetallicRoughness.baseColorTexture.index = 0;
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  material.doubleSided = true;
  model.materials.push_back(material);
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(sampler);
  tinygltf::Texture texture;
  texture.sampler = 0;
  texture.source = 0;
  model.textures.push_back(texture);
  tinygltf::Image image;
  image.uri = texture_name;
  image.mimeType = "image/png";
  model.images.push_back(image);
  // The PNG itself through OpenCV: tinygltf's image writer is not compiled into Debian's library.
  cv::Mat png(int(hand.texture.height), int(hand.texture.width), CV_8UC3);
  for (uint32_t y = 0; y < hand.texture.height; ++y)
    for (uint32_t x = 0; x < hand.texture.width; ++x)
      for (uint32_t c = 0; c < 3; ++c)  // OpenCV stores BGR
        png.at<cv::Vec3b>(int(y), int(x))[int(2 - c)] =
            uint8_t(std::lround(std::clamp(linear_to_srgb(hand.texture.at(x, y, c)), 0.0, 1.0) * 255.0));
  std::filesystem::create_directories(dir);
  if (!cv::imwrite((dir / texture_name).string(), png, {cv::IMWRITE_PNG_COMPRESSION, 9}))
    throw HandTemplateError("could not write " + (dir / texture_name).string());

  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model, file.string(), false, false, true, false))
    throw HandTemplateError("could not write " + file.string());
}

namespace {

// The accessor's elements as doubles, `components` per element; checks type and range.
std::vector<double> read_accessor(const tinygltf::Model& model, int index, int type, const std::string& what,
                                  const std::string& where) {
  auto fail = [&](const std::string& why) { return HandTemplateError(where + ": " + what + " " + why); };
  if (index < 0 || index >= int(model.accessors.size())) throw fail("is missing");
  const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
  if (accessor.type != type) throw fail("has the wrong element type");
  if (accessor.bufferView < 0 || accessor.bufferView >= int(model.bufferViews.size())) throw fail("has no buffer view");
  const tinygltf::BufferView& view = model.bufferViews[size_t(accessor.bufferView)];
  if (view.buffer < 0 || view.buffer >= int(model.buffers.size())) throw fail("has no buffer");
  const auto& data = model.buffers[size_t(view.buffer)].data;
  const int components = tinygltf::GetNumComponentsInType(uint32_t(type));
  const int component_size = tinygltf::GetComponentSizeInBytes(uint32_t(accessor.componentType));
  if (components <= 0 || component_size <= 0) throw fail("has an unknown component type");
  const size_t stride = view.byteStride ? view.byteStride : size_t(components * component_size);
  const size_t start = view.byteOffset + accessor.byteOffset;
  if (accessor.count > 0 &&
      (start + stride * (accessor.count - 1) + size_t(components * component_size) > data.size() ||
       start + stride * (accessor.count - 1) + size_t(components * component_size) > view.byteOffset + view.byteLength))
    throw fail("runs past the end of its buffer (is the .bin file complete?)");
  std::vector<double> out;
  out.reserve(accessor.count * size_t(components));
  for (size_t i = 0; i < accessor.count; ++i)
    for (int c = 0; c < components; ++c) {
      const unsigned char* p = data.data() + start + i * stride + size_t(c * component_size);
      double value = 0;
      switch (accessor.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); value = f; break; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: value = accessor.normalized ? p[0] / 255.0 : p[0]; break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p, 2); value = accessor.normalized ? u / 65535.0 : u; break; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p, 4); value = u; break; }
        default: throw fail("has an unsupported component type " + std::to_string(accessor.componentType));
      }
      out.push_back(value);
    }
  return out;
}

Eigen::Isometry3d node_local(const tinygltf::Node& node) {
  Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
  if (node.matrix.size() == 16) {
    Eigen::Matrix4d m;
    for (int column = 0; column < 4; ++column)
      for (int row = 0; row < 4; ++row) m(row, column) = node.matrix[size_t(column * 4 + row)];
    local.matrix() = m;
    return local;
  }
  if (node.translation.size() == 3) local.translation() = Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]);
  if (node.rotation.size() == 4)
    local.linear() = Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]).normalized().toRotationMatrix();
  return local;
}

}  // namespace

HandTemplate load_hand_template(const std::filesystem::path& dir, bool is_left) {
  return load_hand_template(hand_template_file(dir, is_left));
}

HandTemplate load_hand_template(const std::filesystem::path& gltf_file) {
  const std::string where = "hand template " + gltf_file.string();
  if (!std::filesystem::exists(gltf_file))
    throw HandTemplateError(where + ": no such file (regenerate with `cmake --build build --target regenerate_hand_template`)");
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  if (!loader.LoadASCIIFromFile(&model, &error, &warning, gltf_file.string()))
    throw HandTemplateError(where + ": not a readable glTF file: " + error);
  if (model.skins.size() != 1 || model.meshes.size() != 1 || model.meshes[0].primitives.size() != 1)
    throw HandTemplateError(where + ": expected one skinned mesh with one primitive");
  HandTemplate hand;
  const tinygltf::Mesh& mesh = model.meshes[0];
  hand.is_left = mesh.name.find("left") != std::string::npos;

  // Bones by name, so that the file's joint order may differ from ours.
  const tinygltf::Skin& skin = model.skins[0];
  std::map<std::string, int> bone_by_name;
  for (int bone = 0; bone < kBoneCount; ++bone) bone_by_name[bone_name(bone)] = bone;
  std::vector<int> bone_of_joint(skin.joints.size(), -1);
  std::array<int, kBoneCount> node_of_bone;
  node_of_bone.fill(-1);
  for (size_t j = 0; j < skin.joints.size(); ++j) {
    const int node = skin.joints[j];
    if (node < 0 || node >= int(model.nodes.size())) throw HandTemplateError(where + ": skin joint " + std::to_string(j) + " is not a node");
    const auto found = bone_by_name.find(model.nodes[size_t(node)].name);
    if (found == bone_by_name.end())
      throw HandTemplateError(where + ": joint '" + model.nodes[size_t(node)].name + "' is not a bone of the tracker's hand");
    bone_of_joint[j] = found->second;
    node_of_bone[size_t(found->second)] = node;
  }
  std::vector<int> parent_node(model.nodes.size(), -1);
  for (size_t n = 0; n < model.nodes.size(); ++n)
    for (int child : model.nodes[n].children)
      if (child >= 0 && child < int(model.nodes.size())) parent_node[size_t(child)] = int(n);
  for (int bone = 0; bone < kBoneCount; ++bone) {
    const int node = node_of_bone[size_t(bone)];
    if (node < 0) throw HandTemplateError(where + ": bone '" + bone_name(bone) + "' is missing");
    if (bone_parent(bone) >= 0 && parent_node[size_t(node)] != node_of_bone[size_t(bone_parent(bone))])
      throw HandTemplateError(where + ": bone '" + bone_name(bone) + "' is not a child of '" + bone_name(bone_parent(bone)) + "'");
    Eigen::Isometry3d global = Eigen::Isometry3d::Identity();
    for (int n = node; n >= 0; n = parent_node[size_t(n)]) global = node_local(model.nodes[size_t(n)]) * global;
    hand.rest[size_t(bone)].frame = global;
    const tinygltf::Value& length = model.nodes[size_t(node)].extras.Get("length_m");
    if (!length.IsNumber()) throw HandTemplateError(where + ": bone '" + bone_name(bone) + "' has no extras.length_m");
    hand.rest[size_t(bone)].length_m = length.GetNumberAsDouble();
  }

  const tinygltf::Primitive& primitive = mesh.primitives[0];
  if (primitive.mode != TINYGLTF_MODE_TRIANGLES) throw HandTemplateError(where + ": the mesh is not a triangle list");
  auto attribute = [&](const char* name, int type) {
    const auto found = primitive.attributes.find(name);
    return read_accessor(model, found == primitive.attributes.end() ? -1 : found->second, type, std::string("attribute ") + name, where);
  };
  const auto positions = attribute("POSITION", TINYGLTF_TYPE_VEC3), normals = attribute("NORMAL", TINYGLTF_TYPE_VEC3),
             uvs = attribute("TEXCOORD_0", TINYGLTF_TYPE_VEC2), joints = attribute("JOINTS_0", TINYGLTF_TYPE_VEC4),
             weights = attribute("WEIGHTS_0", TINYGLTF_TYPE_VEC4);
  const size_t n = positions.size() / 3;
  if (normals.size() != 3 * n || uvs.size() != 2 * n || joints.size() != 4 * n || weights.size() != 4 * n)
    throw HandTemplateError(where + ": the vertex attributes differ in count");
  for (size_t i = 0; i < n; ++i) {
    HandVertex v{};
    for (int c = 0; c < 3; ++c) {
      v.position_u[c] = float(positions[3 * i + c]);
      v.normal_v[c] = float(normals[3 * i + c]);
    }
    v.position_u[3] = float(uvs[2 * i]);
    v.normal_v[3] = float(uvs[2 * i + 1]);
    for (int k = 0; k < 4; ++k) {
      const double joint = joints[4 * i + k];
      if (joint >= double(bone_of_joint.size()))
        throw HandTemplateError(where + ": vertex " + std::to_string(i) + " names joint " + std::to_string(joint) + " of a " +
                                std::to_string(bone_of_joint.size()) + "-joint skin");
      v.joints[k] = float(bone_of_joint[size_t(joint)]);
      v.weights[k] = float(weights[4 * i + k]);
    }
    hand.vertices.push_back(v);
  }
  for (double index : read_accessor(model, primitive.indices, TINYGLTF_TYPE_SCALAR, "the index list", where))
    hand.indices.push_back(uint32_t(index));
  // Where the hand's triangles end and the forearm's begin, and the widths shape adaption divides by.
  auto extra = [&](const char* name) {
    const tinygltf::Value& value = mesh.extras.Get(name);
    if (!value.IsNumber())
      throw HandTemplateError(where + ": the mesh has no extras." + name +
                              " (a template from before the forearm: regenerate with `cmake --build build --target "
                              "regenerate_hand_template`)");
    return value.GetNumberAsDouble();
  };
  const double hand_indices = extra("hand_index_count");
  if (!(hand_indices >= 0 && hand_indices <= double(hand.indices.size()) && hand_indices == std::floor(hand_indices)))
    throw HandTemplateError(where + ": extras.hand_index_count " + std::to_string(hand_indices) + " is not a count within the " +
                            std::to_string(hand.indices.size()) + " indices");
  hand.hand_index_count = uint32_t(hand_indices);
  hand.palm_width_m = extra("palm_width_m");
  hand.arm_width_m = extra("arm_width_m");

  // The base color texture: sRGB in the file, linear here.
  if (primitive.material < 0 || primitive.material >= int(model.materials.size()))
    throw HandTemplateError(where + ": the mesh has no material");
  const int texture = model.materials[size_t(primitive.material)].pbrMetallicRoughness.baseColorTexture.index;
  if (texture < 0 || texture >= int(model.textures.size()) || model.textures[size_t(texture)].source < 0 ||
      model.textures[size_t(texture)].source >= int(model.images.size()))
    throw HandTemplateError(where + ": the material has no base color texture");
  const tinygltf::Image& image = model.images[size_t(model.textures[size_t(texture)].source)];
  if (image.width <= 0 || image.height <= 0 || image.bits != 8 || image.component < 3 ||
      image.image.size() != size_t(image.width) * size_t(image.height) * size_t(image.component))
    throw HandTemplateError(where + ": the skin texture '" + image.uri + "' could not be read as an 8-bit RGB(A) image");
  hand.texture = HostImage(uint32_t(image.width), uint32_t(image.height), PixelFormat::RGBA32F);
  for (uint32_t y = 0; y < hand.texture.height; ++y)
    for (uint32_t x = 0; x < hand.texture.width; ++x) {
      for (uint32_t c = 0; c < 3; ++c)
        hand.texture.at(x, y, c) = float(srgb_to_linear(image.image[(size_t(y) * image.width + x) * size_t(image.component) + c] / 255.0));
      hand.texture.at(x, y, 3) = 1.0f;
    }
  validate_hand_template(hand, where);
  return hand;
}

void validate_hand_template(const HandTemplate& hand, const std::string& where) {
  auto fail = [&](const std::string& why) { return HandTemplateError(where + ": " + why); };
  if (hand.vertices.empty() || hand.indices.empty() || hand.indices.size() % 3) throw fail("no triangles");
  for (uint32_t index : hand.indices)
    if (index >= hand.vertices.size()) throw fail("index " + std::to_string(index) + " is past the last vertex");
  for (size_t i = 0; i < hand.vertices.size(); ++i) {
    const HandVertex& v = hand.vertices[i];
    double sum = 0;
    for (int k = 0; k < 4; ++k) {
      if (!(v.weights[k] >= 0) || !(v.joints[k] >= 0 && v.joints[k] < kBoneCount) || v.joints[k] != std::floor(v.joints[k]))
        throw fail("vertex " + std::to_string(i) + " has a bad influence");
      sum += v.weights[k];
    }
    if (std::abs(sum - 1.0) > 1e-3) throw fail("vertex " + std::to_string(i) + "'s weights sum to " + std::to_string(sum));
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(v.position_u[c]) || !std::isfinite(v.normal_v[c])) throw fail("vertex " + std::to_string(i) + " is not finite");
    if (v.position_u[3] < 0 || v.position_u[3] > 1 || v.normal_v[3] < 0 || v.normal_v[3] > 1)
      throw fail("vertex " + std::to_string(i) + "'s texture coordinates leave [0, 1]");
  }
  for (int bone = 0; bone < kBoneCount; ++bone) {
    const Eigen::Matrix3d r = hand.rest[bone].frame.linear();
    if (!hand.rest[bone].frame.matrix().allFinite() || (r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-4 ||
        r.determinant() < 0 || !(hand.rest[bone].length_m >= 0))
      throw fail("bone '" + bone_name(bone) + "' has no rigid rest frame or a negative length");
  }
  if (hand.texture.width == 0 || hand.texture.format != PixelFormat::RGBA32F) throw fail("no skin texture");
  if (hand.hand_index_count == 0 || hand.hand_index_count % 3 || hand.hand_index_count > hand.indices.size())
    throw fail("hand_index_count " + std::to_string(hand.hand_index_count) + " is not a whole number of triangles in 1.." +
               std::to_string(hand.indices.size() / 3) + " triangles (the hand's come first, the forearm's after)");
  for (auto [width, name] : {std::pair{hand.palm_width_m, "palm_width_m"}, std::pair{hand.arm_width_m, "arm_width_m"}})
    if (!(std::isfinite(width) && width > 0.0 && width < 1.0))
      throw fail(std::string(name) + " " + std::to_string(width) + " is not a width in (0, 1) m");
}

}  // namespace rt::hand
