// The peer check: the committed Lumi-Net (assets/lumi/lumi_net.bin, trained by scripts/train-lumi)
// on the GPU kernels against its committed ONNX export (assets/lumi/lumi_net.onnx) run by OpenCV
// DNN's CPU backend, on the same input tensors (those the GPU's lumi_input computed from random
// warped views, 4 views, the ONNX's 61x45 at scale 2). The head's logits agree within 1e-4
// absolute + 1e-4 relative (fp32 sums in different orders through three 3x3 layers). Also the C++
// reference of the network against OpenCV, and no NaN or Inf.
#include <opencv2/dnn.hpp>

#include <cstring>
#include <random>

#include "config/assets.h"
#include "ibr/lumi_net_model.h"
#include "pipeline/lumi_net.h"
#include "shared/lumi_net.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/lumi_tensors.h"

using namespace rt;

namespace {

constexpr uint32_t kViews = 4, kSmallWidth = 61, kSmallHeight = 45;  // the ONNX export's input size

passes::LumiTensor download_tensor(vk::Buffer& buffer, uint32_t channels) {
  passes::LumiTensor t(kViews, channels, kSmallWidth, kSmallHeight);
  const std::vector<std::byte> bytes = vk::download(test::gpu(), buffer);
  std::memcpy(t.values.data(), bytes.data(), t.size_bytes());
  return t;
}

cv::Mat blob_of(const passes::LumiTensor& t) {
  const int shape[4] = {int(t.views), int(t.channels), int(t.height), int(t.width)};
  cv::Mat blob(4, shape, CV_32F);
  std::memcpy(blob.ptr<float>(), t.values.data(), t.size_bytes());
  return blob;
}

}  // namespace

TEST_CASE("Lumi-Net's kernels match OpenCV DNN running the committed ONNX", "[lumi_net][gpu][onnx]") {
  test::NoValidationErrors no_errors;
  const ibr::LumiNetModel model = ibr::load_lumi_net(ibr::default_lumi_net_path());
  REQUIRE(model.shape.scale == 2);
  std::mt19937 rng(61);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const uint32_t width = kSmallWidth * 2, height = kSmallHeight * 2;
  const HostImage fused = test::random_fused_depth(rng, width, height);
  const HostImage warped = test::random_image(rng, width, height * kViews, PixelFormat::RGBA32F);
  HostImage features = test::random_image(rng, width, height * kViews, PixelFormat::RGBA32F);
  for (size_t i = 0; i < features.texels.size(); i += 4) features.texels[i + 3] = unit(rng) < 0.6f ? 1.0f : 0.0f;

  pipeline::LumiNetBlender net(test::gpu(), model, width, height, kViews);
  {
    test::PassHarness gpu("lumi_net peer check");
    net.add_to(gpu.graph(), gpu.input("fused depth", fused), gpu.input("warped", warped), gpu.input("features", features),
               gpu.output("portrait", width, height, PixelFormat::RGBA32F),
               gpu.output("portrait depth", width, height, PixelFormat::R32F), kViews);
    gpu.run();
  }
  const passes::LumiTensor inputs = download_tensor(net.inputs(), RT_LUMI_INPUT_CHANNELS);
  const passes::LumiTensor coverage = download_tensor(net.coverage(), 1);
  const passes::LumiTensor logits = download_tensor(net.logits(), RT_LUMI_HEAD_CHANNELS);
  passes::LumiTensor seen = coverage;
  for (float& s : seen.values) s = s > 0.0f ? 1.0f : 0.0f;

  cv::dnn::Net onnx = cv::dnn::readNetFromONNX((config::assets_dir() / "lumi" / "lumi_net.onnx").string());
  onnx.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  onnx.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  onnx.setInput(blob_of(inputs), "inputs");
  onnx.setInput(blob_of(seen), "seen");
  const cv::Mat out = onnx.forward("logits");
  REQUIRE(out.total() == logits.values.size());
  passes::LumiTensor opencv(kViews, RT_LUMI_HEAD_CHANNELS, kSmallWidth, kSmallHeight);
  std::memcpy(opencv.values.data(), out.ptr<float>(), opencv.size_bytes());

  RT_REQUIRE_MATCHES(test::as_image(logits), test::as_image(opencv), 1e-4, 1e-4);
  RT_REQUIRE_MATCHES(test::as_image(pipeline::lumi_net_logits_reference(model, inputs, coverage)), test::as_image(opencv),
                     1e-4, 1e-4);
}
