// The barrier rules of the frame graph, on plain state (no device needed).
#include <catch2/catch.hpp>

#include "vulkan/barriers.h"

using namespace rt::vk;

TEST_CASE("first write of a fresh image transitions its layout", "[barriers]") {
  ResourceState state;
  const auto plan = plan_access(state, access::compute_write, true);
  REQUIRE(plan);
  CHECK(plan->old_layout == VK_IMAGE_LAYOUT_UNDEFINED);
  CHECK(plan->new_layout == VK_IMAGE_LAYOUT_GENERAL);
  CHECK(plan->src_stages == VK_PIPELINE_STAGE_2_NONE);
  CHECK(state.write_access == VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

TEST_CASE("first write of a fresh buffer needs no barrier", "[barriers]") {
  ResourceState state;
  CHECK_FALSE(plan_access(state, access::compute_write, false));
}

TEST_CASE("read after write waits for the write and makes it visible", "[barriers]") {
  ResourceState state;
  plan_access(state, access::compute_write, true);
  const auto plan = plan_access(state, access::compute_read, true);
  REQUIRE(plan);  // dispatch-to-dispatch: the hazard the validation layer of 1.3.239 misses
  CHECK(plan->src_stages == VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  CHECK(plan->src_access == VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  CHECK(plan->dst_access == VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  CHECK(plan->old_layout == plan->new_layout);
}

TEST_CASE("a second read of the same kind needs no new barrier", "[barriers]") {
  ResourceState state;
  plan_access(state, access::compute_write, true);
  REQUIRE(plan_access(state, access::compute_read, true));
  CHECK_FALSE(plan_access(state, access::compute_read, true));
}

TEST_CASE("write after read waits for the reads only (execution dependency)", "[barriers]") {
  // A buffer read in the vertex and fragment stages, then written by a compute shader: the write
  // waits for the reading stages, and there is nothing to make available (reads write nothing).
  ResourceState buffer;
  CHECK_FALSE(plan_access(buffer, access::graphics_read, false));  // nothing written before it
  const auto plan = plan_access(buffer, access::compute_write, false);
  REQUIRE(plan);
  CHECK(plan->src_stages == (VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT));
  CHECK(plan->src_access == VK_ACCESS_2_NONE);
  CHECK(plan->dst_stages == VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  CHECK(plan->dst_access == VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);

  // Write, read, write on an image: the second write waits for the read's stage; its source access
  // holds no read (at most the first write, which the read's barrier already made visible).
  ResourceState image;
  plan_access(image, access::compute_write, true);
  REQUIRE(plan_access(image, access::compute_read, true));
  const auto again = plan_access(image, access::compute_write, true);
  REQUIRE(again);
  CHECK(again->src_stages == VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  CHECK((again->src_access & ~VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT) == 0);
  CHECK(again->dst_stages == VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  CHECK(again->dst_access == VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  CHECK(again->old_layout == VK_IMAGE_LAYOUT_GENERAL);
  CHECK(again->new_layout == VK_IMAGE_LAYOUT_GENERAL);
}

TEST_CASE("write after write waits for the earlier write", "[barriers]") {
  ResourceState state;
  plan_access(state, access::compute_write, false);
  const auto plan = plan_access(state, access::compute_write, false);
  REQUIRE(plan);
  CHECK(plan->src_access == VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

TEST_CASE("a layout change after a read waits for that read", "[barriers]") {
  ResourceState state;
  plan_access(state, access::transfer_write, true);
  plan_access(state, access::compute_read, true);
  const auto plan = plan_access(state, access::transfer_read, true);
  REQUIRE(plan);
  CHECK(plan->old_layout == VK_IMAGE_LAYOUT_GENERAL);
  CHECK(plan->new_layout == VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  // The copy that wrote it is already ordered before that read by the read's own barrier.
  CHECK(plan->src_stages == VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
}

TEST_CASE("a reader in another stage after a read-only transition still waits", "[barriers]") {
  ResourceState state;
  plan_access(state, access::compute_write, true);
  REQUIRE(plan_access(state, access::transfer_read, true));  // transition to TRANSFER_SRC
  const auto plan = plan_access(state, access::host_read, false);
  REQUIRE(plan);
  CHECK(plan->src_stages == VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT);
}

TEST_CASE("reads and writes are classified by their access bits", "[barriers]") {
  CHECK(writes(access::compute_write.access));
  CHECK_FALSE(reads(access::compute_write.access));
  CHECK(reads(access::compute_read.access));
  CHECK_FALSE(writes(access::compute_read.access));
  CHECK(reads(access::compute_read_write.access));
  CHECK(writes(access::compute_read_write.access));
}
