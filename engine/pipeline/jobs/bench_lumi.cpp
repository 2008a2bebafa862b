// `remotetouch bench lumi`: Lumi-Net's kernels against OpenCV DNN running the committed ONNX
// export on the same input tensors, in the same process, on the same CPU cores (on lavapipe the
// GPU is those cores too), and the lumigraph blending (ibr_blend) for scale. The GPU times come
// from the frame graph's timestamp queries; OpenCV's is the wall time of its forward pass. The
// input is one frame of the clap scene, four views (the ONNX export's), site A's user for site
// B's eye.
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

#include "geometry/target_view.h"
#include "ibr/camera_selection.h"
#include "pipeline/gpu_session.h"
#include "pipeline/ibr_renderer.h"
#include "pipeline/jobs.h"
#include "pipeline/site_simulator.h"
#include "shared/lumi_net.h"

namespace rt::pipeline {
namespace {

constexpr uint32_t kLumiWarmUpFrames = 2;
constexpr uint32_t kOnnxViews = 4;  // the export splits its inputs into this many views

// The layers the ONNX export holds: from the input tensors to the head's logits.
bool is_network_pass(const std::string& name) {
  for (const char* prefix : {"lumi_conv", "lumi_pool", "lumi_head"})
    if (name.rfind(prefix, 0) == 0) return true;
  return false;
}

double lumi_median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

cv::Mat download_blob(vk::Context& context, vk::Buffer& buffer, uint32_t channels, uint32_t width, uint32_t height,
                      bool as_seen) {
  const int shape[4] = {int(kOnnxViews), int(channels), int(height), int(width)};
  cv::Mat blob(4, shape, CV_32F);
  const std::vector<std::byte> bytes = vk::download(context, buffer);
  if (bytes.size() < blob.total() * sizeof(float)) throw std::logic_error("bench lumi: a tensor is smaller than expected");
  std::memcpy(blob.ptr<float>(), bytes.data(), blob.total() * sizeof(float));
  if (as_seen)  // the export takes "seen" (coverage > 0) as 0 or 1
    for (float* v = blob.ptr<float>(); v != blob.ptr<float>() + blob.total(); ++v) *v = *v > 0.0f ? 1.0f : 0.0f;
  return blob;
}

// Multiply-adds of the network's layers, times two: the work both sides do.
double network_flops(const ibr::LumiNetModel& model, uint32_t small_pixels) {
  double flops = 0;
  for (const ibr::LumiLayer& layer : ibr::lumi_layers(model.shape))
    flops += 2.0 * layer.in_channels * layer.out_channels * layer.kernel_size * layer.kernel_size;
  return flops * small_pixels * kOnnxViews;
}

}  // namespace

int run_bench_lumi(const RunOptions& options, const IbrSettings& base, const std::filesystem::path& onnx_path) {
  GpuSession session(options);
  vk::Context& context = session.context();
  sim::Scene scene = sim::load_scene(sim::resolve_scene("clap"));
  scene.frame_count = 1;
  SiteSimulator simulator(context, scene, Site::A);
  const sim::RgbdFrame frame = *simulator.next_frame();
  std::vector<passes::IbrCameraModel> cameras = simulator.renderer().camera_models();
  std::vector<Eigen::Vector3d> positions;
  for (const auto& camera : cameras) positions.push_back(camera.color.position_in_site());
  const Eigen::Vector3d eye = map_point(Site::B, Site::A, scene.at(Site::B).site.seat.head_centre_m);
  const uint32_t width = options.width, height = options.height;
  const Camera target = target_view_camera(eye, scene.at(Site::A).site.screen, width, height);
  const auto selection = ibr::select_cameras(positions, ibr::TouchingHand::Right, kOnnxViews);

  // Both blendings on the same frame, each in its own graph; the warp before them is the same.
  auto timed = [&](IbrBlending blending) {
    IbrSettings settings = base;
    settings.width = width;
    settings.height = height;
    settings.views = kOnnxViews;
    settings.blending = blending;
    settings.split_warp = true;  // lumigraph blending as its own pass, to set beside the network's
    auto renderer = std::make_unique<IbrRenderer>(context, cameras, settings);
    renderer->prepare(frame.cameras, selection, target);
    for (uint32_t i = 0; i < kLumiWarmUpFrames + options.frames; ++i) {
      if (i == kLumiWarmUpFrames) renderer->graph().reset_timings();
      session.run_frame(renderer->graph(), i);
    }
    return renderer;
  };
  const auto ulr = timed(IbrBlending::Ulr);
  const auto lumi = timed(IbrBlending::Lumi);
  LumiNetBlender& net = *lumi->lumi_net();
  const ibr::LumiNetModel& model = net.model();
  const uint32_t scale = model.shape.scale;
  const uint32_t sw = passes::lumi_small_size(width, scale), sh = passes::lumi_small_size(height, scale);

  double ulr_ms = 0, network_ms = 0, chain_ms = 0;
  for (const auto& timing : ulr->graph().timings())
    if (timing.name == "ibr_blend") ulr_ms += timing.median_ms;
  nlohmann::json lumi_passes = nlohmann::json::object();
  for (const auto& timing : lumi->graph().timings()) {
    if (timing.name.rfind("lumi_", 0) != 0) continue;
    lumi_passes[timing.name] = timing.median_ms;
    chain_ms += timing.median_ms;
    if (is_network_pass(timing.name)) network_ms += timing.median_ms;
  }

  // OpenCV DNN on the tensors lumi_input wrote for the last frame.
  cv::dnn::Net onnx;
  try {
    onnx = cv::dnn::readNetFromONNX(onnx_path.string());
  } catch (const cv::Exception& error) {
    throw std::runtime_error("bench lumi: OpenCV DNN cannot read '" + onnx_path.string() + "' (" + error.what() +
                             "); scripts/train-lumi writes it next to the weights");
  }
  onnx.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  onnx.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  const cv::Mat inputs = download_blob(context, net.inputs(), RT_LUMI_INPUT_CHANNELS, sw, sh, false);
  const cv::Mat seen = download_blob(context, net.coverage(), 1, sw, sh, true);
  std::vector<double> opencv_ms;
  cv::Mat out;
  for (uint32_t i = 0; i < 1 + options.frames; ++i) {
    onnx.setInput(inputs, "inputs");
    onnx.setInput(seen, "seen");
    const auto start = std::chrono::steady_clock::now();
    out = onnx.forward("logits");
    if (i > 0) opencv_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  // The same logits both ways, or the comparison means nothing.
  const std::vector<std::byte> gpu_bytes = vk::download(context, net.logits());
  const size_t count = size_t(kOnnxViews) * RT_LUMI_HEAD_CHANNELS * sw * sh;
  if (out.total() != count)
    throw std::runtime_error("bench lumi: OpenCV DNN gave " + std::to_string(out.total()) + " logits, expected " +
                             std::to_string(count) + " (is '" + onnx_path.string() + "' the export of these weights?)");
  const float* gpu = reinterpret_cast<const float*>(gpu_bytes.data());
  double max_difference = 0;
  for (size_t k = 0; k < count; ++k) {
    const double d = std::abs(double(gpu[k]) - double(out.ptr<float>()[k]));
    if (!std::isfinite(gpu[k]) || !std::isfinite(out.ptr<float>()[k]))
      throw std::runtime_error("bench lumi: a logit is not finite");
    max_difference = std::max(max_difference, d);
  }

  const double cv_ms = lumi_median(opencv_ms);
  const double flops = network_flops(model, sw * sh);
  const double ratio = network_ms > 0 ? cv_ms / network_ms : 0.0;
  nlohmann::json report = {
      {"device", context.device_name()},
      {"frames", options.frames},
      {"width", width},
      {"height", height},
      {"network_width", sw},
      {"network_height", sh},
      {"views", kOnnxViews},
      {"weights", lumi_weights_path(base).string()},
      {"onnx", onnx_path.string()},
      {"channels", model.shape.channels},
      {"blocks", model.shape.blocks},
      {"scale", scale},
      {"gflop_per_frame", flops * 1e-9},
      {"gpu_ms", lumi_passes},
      {"gpu_ms_network", network_ms},
      {"gpu_ms_lumi_chain", chain_ms},
      {"gpu_ms_ulr_blend", ulr_ms},
      {"opencv_ms", cv_ms},
      {"opencv_threads", cv::getNumThreads()},
      {"cpu_cores", std::thread::hardware_concurrency()},
      {"opencv_over_kernels", ratio},
      {"max_logit_difference", max_difference},
  };
  std::printf("bench lumi on %s: clap, one frame, %ux%u, %u views; the network at %ux%u (1/%u), C = %u, %u blocks, "
              "%.2f GFLOP a frame; median of %u frames\n",
              context.device_name().c_str(), width, height, kOnnxViews, sw, sh, scale, model.shape.channels,
              model.shape.blocks, flops * 1e-9, options.frames);
  std::printf("\n%-38s %10s %10s\n", "", "ms", "GFLOP/s");
  std::printf("%-38s %10.2f %10.2f\n", "Lumi-Net layers, GPU kernels", network_ms, network_ms > 0 ? flops / network_ms * 1e-6 : 0.0);
  std::printf("%-38s %10.2f %10.2f\n", "Lumi-Net layers, OpenCV DNN (ONNX)", cv_ms, cv_ms > 0 ? flops / cv_ms * 1e-6 : 0.0);
  std::printf("%-38s %10.2f\n", "Lumi-Net whole chain, GPU kernels", chain_ms);
  std::printf("%-38s %10.2f\n", "ULR blend (ibr_blend), GPU", ulr_ms);
  std::printf("\nOpenCV DNN / kernels: %.2fx (%s; OpenCV on %d threads, %u cores); largest logit difference %.2g\n", ratio,
              ratio >= 1.0 ? "the kernels are faster" : "OpenCV is faster", cv::getNumThreads(),
              std::thread::hardware_concurrency(), max_difference);
  std::printf("Lumi-Net's chain / ULR blend: %.1fx\n", ulr_ms > 0 ? chain_ms / ulr_ms : 0.0);
  std::printf("\nper-pass GPU ms:\n%s", vk::format_profile(lumi->graph().timings()).c_str());
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_lumi.json") << report.dump(2) << "\n";
  std::printf("\nwritten to %s\n", (options.out / "bench_lumi.json").string().c_str());
  session.report_capture();
  return 0;
}

}  // namespace rt::pipeline
