#pragma once
// The receiver's geometry hand (paper sections 3.1.2 and 3.1.3): the remote user's tracked
// skeleton drives the skinned template, fitted once to that user's bone lengths (shape
// adaption, Eq. 2) and continually to their skin color (appearance adaption, Eq. 3), drawn
// from the local eye's target view. The skeleton and the camera are in the same frame (the
// remote site's), so the outputs are pixel-aligned with the image-based portrait of that view.
//
// Per frame: set_pose() on the CPU, then the graph that add_to() filled runs skinning and
// rasterization. Appearance adaption runs in its own small frame graph (adapt_appearance_from):
// it renders the untouched template texture T, measures it against the portrait and rewrites
// T', which the next frame samples. It cannot live in the frame's graph, because the raster
// reads T' that it writes.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "geometry/camera.h"
#include "hand/appearance_adaption.h"
#include "hand/hand_template.h"
#include "hand/shading_fit.h"
#include "pipeline/hand_settings.h"
#include "passes/hand_color_reduce.h"
#include "passes/hand_color_stats.h"
#include "passes/hand_color_transfer.h"
#include "passes/hand_raster.h"
#include "passes/hand_resolve.h"
#include "passes/hand_shading_stats.h"
#include "passes/hand_skinning.h"
#include "vulkan/frame_graph.h"

namespace rt::pipeline {

class HandRenderer {
 public:
  HandRenderer(vk::Context& context, const std::filesystem::path& template_dir, uint32_t width, uint32_t height,
               const HandRendererOptions& options = {});
  ~HandRenderer();
  HandRenderer(const HandRenderer&) = delete;
  HandRenderer& operator=(const HandRenderer&) = delete;

  // Per frame, CPU side (between graph runs). A skeleton that cannot be posed keeps the last
  // good pose (pose_error() says why); before any good pose nothing is drawn. The forearm is
  // drawn only while the posed skeleton has a tracked elbow at a plausible distance from the
  // wrist (hand::forearm_tracked); otherwise the hand alone.
  void set_pose(const HandSkeleton& skeleton_in_site, const Camera& target_view);
  void request_shape_adaption();  // again at the next well-tracked frame
  void add_to(vk::FrameGraph& graph);

  vk::Image& color() { return *color_; }  // rgba32f straight alpha
  vk::Image& depth() { return *depth_; }  // r32f metres of camera z, 0 = no hand
  vk::Image& mask() { return *mask_; }    // r32f coverage in [0, 1]

  // Eq. 3 from the image-based portrait of the same target view (rgba32f straight alpha, r32f
  // metres, 0 = nothing): runs now, only while the hand is tracked, and farther from the screen
  // than d_max (where the cameras see it well) once a frame there has fitted; until then also
  // closer, provisionally (hand::AppearanceAdaption); returns whether it ran. It reads the small state
  // back to learn whether the frame counted (a region under min-region-fraction does not).
  bool adapt_appearance_from(vk::Image& portrait_color, vk::Image& portrait_depth);
  // Whether adapt_appearance_from would run with the current pose: callers skip the work that
  // would only feed it otherwise.
  bool appearance_adaption_possible() const;
  // Possible, and nothing fitted yet (or the fit restarted): the texture is still the template's,
  // not the user's. A caller then adapts from the portrait before drawing the hand, so that the
  // first hand shown already wears the user's colours; later fits follow the display.
  bool awaits_first_fit() const { return appearance_adaption_possible() && appearance_.status().frames_fitted == 0; }
  void reset_appearance();
  shader_abi::AppearanceState appearance_state();  // reads the GPU state back

  // Appearance adaption's record, counted in displayed frames (hand/appearance_adaption.h). The
  // receiver tells it each displayed frame, from the thread that owns this renderer: one more, or
  // the total so far from a counter the display thread keeps.
  void note_frame_displayed(uint64_t count = 1) { appearance_.frame_displayed(count); }
  void sync_frames_displayed(uint64_t total) { appearance_.sync_frames_displayed(total); }
  hand::AppearanceStatus appearance_status() const { return appearance_.status(); }
  // The light estimate the mesh is shaded with: unlit until a frame beyond d_max has fitted (a
  // provisional fit leaves it unlit), or when off.
  const hand::ShadingFit& shading_fit() const { return shading_; }
  // For the events log: "fitted", "stale", "refitted", "rejected" (hand::AppearanceAdaption).
  std::vector<nlohmann::json> take_appearance_events() { return appearance_.take_events(); }
  vk::FrameGraph* appearance_graph() { return appearance_graph_.get(); }

  bool has_pose() const { return has_pose_; }
  bool shape_adapted() const { return shape_adapted_; }
  bool forearm_drawn() const { return has_pose_ && forearm_; }
  uint32_t drawn_index_count() const;  // what the raster draws with the current pose
  const std::string& pose_error() const { return pose_error_; }
  double hand_distance_m() const { return hand_distance_m_; }  // averaged joints to the screen
  const hand::HandTemplate& active_template() const;
  const hand::RestSkeleton& active_rest() const { return rest_; }
  const std::vector<shader_abi::HandVertex>& active_rest_vertices() const { return rest_vertices_; }
  const passes::BoneMatrices& bone_matrices() const { return matrices_; }
  std::array<Eigen::Vector3d, kDigitCount> fingertips() const;  // where the mesh's tip joints are
  vk::Buffer& skinned_vertices() { return *skinned_; }

 private:
  void use_template(bool is_left);
  void adapt_shape(const HandSkeleton& skeleton);
  void build_appearance_graph(vk::Image& portrait_color, vk::Image& portrait_depth);

  vk::Context& context_;
  HandRendererOptions options_;
  uint32_t width_, height_;
  hand::HandTemplate right_, left_;
  bool is_left_ = false;
  hand::RestSkeleton rest_{};
  std::vector<shader_abi::HandVertex> rest_vertices_;
  hand::BoneFrames frames_{};
  passes::BoneMatrices matrices_{};
  bool has_pose_ = false, tracked_ = false, shape_adapted_ = false, shape_requested_ = true, forearm_ = false;
  std::string pose_error_;
  double hand_distance_m_ = 0.0;
  passes::RasterViewParams view_{};
  passes::RasterViewParams display_view_{};  // view_ at the supersampled resolution

  passes::HandSkinningPass skinning_;
  passes::HandRasterPass raster_;
  passes::HandColorStatsPass stats_;
  passes::HandColorReducePass reduce_;
  passes::HandColorTransferPass transfer_;
  passes::HandShadingStatsPass shading_stats_;
  std::optional<passes::HandResolvePass> resolve_;  // with supersampling
  vk::Sampler sampler_;
  std::unique_ptr<vk::Buffer> rest_buffer_, indices_, bones_, skinned_, partials_, state_, shading_partials_;
  std::unique_ptr<vk::Image> template_texture_, adapted_texture_, color_, depth_, mask_;
  // What the displayed hand is rasterized into: at the supersampled resolution, then resolved
  // into color_, depth_ and mask_; without supersampling, those three themselves.
  std::unique_ptr<vk::Image> fine_color_, fine_depth_, fine_mask_, display_normal_, display_depth_buffer_;
  std::unique_ptr<vk::Image> template_color_, template_depth_, template_mask_, template_normal_, template_depth_buffer_;
  std::unique_ptr<vk::FrameGraph> appearance_graph_;
  const vk::Image* appearance_portrait_[2] = {nullptr, nullptr};
  hand::AppearanceAdaption appearance_;
  hand::ShadingFit shading_;
  std::array<std::array<float, 4>, 3> raster_shading_{};  // what the frame's raster applies
  shader_abi::AppearanceState appearance_before_{};  // the GPU state as last read back
};

}  // namespace rt::pipeline
