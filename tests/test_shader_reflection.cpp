// Reflection of the real shaders: what pipelines, dispatches and the frame graph rely on.
#include <cstdint>  // the generated SPIR-V headers use uint32_t

#include "composite.comp.h"
#include "hand_alpha.comp.h"
#include "support/gpu_test.h"
#include "vulkan/compute_kernel.h"
#include "vulkan/shader_reflection.h"

using namespace rt;

TEST_CASE("hand_alpha: bindings, qualifiers, formats, push constants, workgroup, knobs", "[reflection]") {
  const vk::ShaderReflection shader = vk::reflect_shader("hand_alpha", hand_alpha_comp_spirv);
  CHECK(shader.stage == VK_SHADER_STAGE_COMPUTE_BIT);
  // One row of pixels per workgroup: the pointwise passes stream memory best that way.
  CHECK(shader.workgroup_size == std::array<uint32_t, 3>{256, 1, 1});
  CHECK(shader.push_constant_size == 4);
  REQUIRE(shader.bindings.size() == 2);
  const vk::ShaderBinding* mask = shader.find_binding("hand_mask");
  const vk::ShaderBinding* alpha = shader.find_binding("hand_alpha");
  REQUIRE(mask);
  REQUIRE(alpha);
  CHECK(mask->binding == 0);
  CHECK(mask->type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  CHECK(mask->image_format == VK_FORMAT_R32_SFLOAT);
  CHECK(mask->readable);
  CHECK_FALSE(mask->writable);
  CHECK(alpha->binding == 1);
  CHECK(alpha->writable);
  CHECK_FALSE(alpha->readable);
  REQUIRE(shader.spec_constants.size() == 2);
  REQUIRE(shader.find_spec_constant("d_min_m"));
  CHECK(shader.find_spec_constant("d_min_m")->constant_id == 0);
  CHECK(shader.find_spec_constant("d_max_m")->constant_id == 1);
  CHECK(shader.find_spec_constant("d_max_m")->type == vk::ScalarType::Float);
}

TEST_CASE("composite writes an 8-bit display image and takes no push constants", "[reflection]") {
  const vk::ShaderReflection shader = vk::reflect_shader("composite", composite_comp_spirv);
  CHECK(shader.push_constant_size == 0);
  REQUIRE(shader.find_binding("display"));
  CHECK(shader.find_binding("display")->image_format == VK_FORMAT_R8G8B8A8_UNORM);
}

TEST_CASE("garbage instead of SPIR-V is refused with the shader's name", "[reflection]") {
  const std::vector<uint32_t> garbage = {1, 2, 3, 4, 5, 6};
  CHECK_THROWS_WITH(vk::reflect_shader("broken", garbage), Catch::Contains("broken"));
}

TEST_CASE("knobs are set by name and type-checked", "[reflection][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const std::vector<vk::Knob> ramp = {{"d_min_m", 0.1f}, {"d_max_m", 0.5f}};
  CHECK_NOTHROW(vk::ComputeKernel(context, "hand_alpha", hand_alpha_comp_spirv, ramp));
  CHECK_THROWS_WITH(vk::ComputeKernel(context, "hand_alpha", hand_alpha_comp_spirv, {ramp[0], {"d_maximum", 0.5f}}),
                    Catch::Contains("no knob 'd_maximum'") && Catch::Contains("d_max_m"));
  CHECK_THROWS_WITH(vk::ComputeKernel(context, "hand_alpha", hand_alpha_comp_spirv, {ramp[0], {"d_max_m", 5}}),
                    Catch::Contains("is a float, given a int"));
  const vk::ComputeKernel kernel(context, "hand_alpha", hand_alpha_comp_spirv, ramp);
  CHECK(kernel.group_count({641, 359, 1}) == std::array<uint32_t, 3>{3, 359, 1});
  CHECK(kernel.group_count({1, 1, 1}) == std::array<uint32_t, 3>{1, 1, 1});
}

TEST_CASE("a kernel refuses to build while a specialization constant of its shader is not set", "[reflection][gpu]") {
  // Otherwise the constant would take the shader's initial value: a second default, which can
  // disagree with the pass's C++ settings.
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  CHECK_THROWS_WITH(vk::ComputeKernel(context, "hand_alpha", hand_alpha_comp_spirv, {{"d_max_m", 0.5f}}),
                    Catch::Contains("shader 'hand_alpha'") && Catch::Contains("'d_min_m' (constant_id 0) is not set") &&
                        !Catch::Contains("d_max_m"));
  CHECK_THROWS_WITH(vk::ComputeKernel(context, "hand_alpha", hand_alpha_comp_spirv),
                    Catch::Contains("'d_min_m' (constant_id 0), 'd_max_m' (constant_id 1) are not set"));
  CHECK_NOTHROW(vk::ComputeKernel(context, "composite", composite_comp_spirv));  // it declares none
  // The rule holds for the graphics kernel's stages too.
  vk::require_spec_constants_set("person_raster (fragment)", vk::reflect_shader("hand_alpha", hand_alpha_comp_spirv),
                                 std::vector<std::string>{"d_min_m", "d_max_m"});
  CHECK_THROWS_WITH(vk::require_spec_constants_set("person_raster (fragment)",
                                                   vk::reflect_shader("hand_alpha", hand_alpha_comp_spirv),
                                                   std::vector<std::string>{"d_max_m"}),
                    Catch::Contains("shader 'person_raster (fragment)'") && Catch::Contains("d_min_m"));
}
