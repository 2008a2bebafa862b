#include "image/image_io.h"

#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace rt {
namespace {

std::string lower_extension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

void enable_openexr() {
  // OpenCV ships EXR support switched off (CVE history); it reads this once, on first EXR use.
  setenv("OPENCV_IO_ENABLE_OPENEXR", "1", 0);
}

}  // namespace

void write_image(const std::filesystem::path& path, const HostImage& image, PngDepth depth) {
  const std::string extension = lower_extension(path);
  const int channels = int(image.channels());
  cv::Mat rgba(int(image.height), int(image.width), CV_32FC(channels), const_cast<float*>(image.texels.data()));
  cv::Mat bgra;
  if (channels == 4) cv::cvtColor(rgba, bgra, cv::COLOR_RGBA2BGRA);
  else bgra = rgba.clone();

  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  bool written = false;
  if (image.format == PixelFormat::R16U) {
    if (extension != ".png") throw std::invalid_argument("cannot write '" + path.string() + "': 16-bit depth goes to .png");
    cv::Mat millimetres;
    bgra.convertTo(millimetres, CV_16U);  // the values themselves: they are integers already
    written = cv::imwrite(path.string(), millimetres);
  } else if (extension == ".exr") {
    enable_openexr();
    written = cv::imwrite(path.string(), bgra);
  } else if (extension == ".png") {
    cv::patchNaNs(bgra, 0.0);
    const double scale = depth == PngDepth::Sixteen ? 65535.0 : 255.0;
    cv::Mat quantised;
    bgra.convertTo(quantised, depth == PngDepth::Sixteen ? CV_16U : CV_8U, scale);  // saturates to the range
    written = cv::imwrite(path.string(), quantised);
  } else {
    throw std::invalid_argument("cannot write '" + path.string() + "': the extension must be .png or .exr");
  }
  if (!written) throw std::runtime_error("OpenCV could not write '" + path.string() + "'");
}

HostImage read_image(const std::filesystem::path& path) {
  if (lower_extension(path) == ".exr") enable_openexr();
  const cv::Mat loaded = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (loaded.empty()) throw std::runtime_error("cannot read image '" + path.string() + "' (missing or not an image)");
  double scale = 1.0;
  if (loaded.depth() == CV_8U) scale = 1.0 / 255.0;
  else if (loaded.depth() == CV_16U) scale = 1.0 / 65535.0;
  else if (loaded.depth() != CV_32F) throw std::runtime_error("image '" + path.string() + "' has an unsupported depth");
  cv::Mat values;
  loaded.convertTo(values, CV_32F);
  // Divide each value, not multiply by the reciprocal (as OpenCV's scaling does): k / 255.0f
  // is what the engine's 8-bit unpacking gives, so a PNG read back equals what was written.
  if (scale != 1.0) {
    const float divisor = float(1.0 / scale);
    for (int row = 0; row < values.rows; ++row) {
      float* value = values.ptr<float>(row);
      for (int i = 0; i < values.cols * values.channels(); ++i) value[i] /= divisor;
    }
  }
  const bool grey = values.channels() == 1;
  cv::Mat rgba;
  if (grey) rgba = values;
  else if (values.channels() == 3) cv::cvtColor(values, rgba, cv::COLOR_BGR2RGBA);
  else cv::cvtColor(values, rgba, cv::COLOR_BGRA2RGBA);
  HostImage image(uint32_t(rgba.cols), uint32_t(rgba.rows), grey ? PixelFormat::R32F : PixelFormat::RGBA32F);
  for (int y = 0; y < rgba.rows; ++y)
    std::memcpy(&image.at(0, uint32_t(y)), rgba.ptr<float>(y), size_t(rgba.cols) * image.channels() * sizeof(float));
  return image;
}

HostImage read_depth_png(const std::filesystem::path& path) {
  const cv::Mat loaded = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (loaded.empty()) throw std::runtime_error("cannot read depth image '" + path.string() + "' (missing or not an image)");
  if (loaded.type() != CV_16UC1)
    throw std::runtime_error("depth image '" + path.string() + "' is not a one-channel 16-bit PNG");
  HostImage image(uint32_t(loaded.cols), uint32_t(loaded.rows), PixelFormat::R16U);
  for (int y = 0; y < loaded.rows; ++y)
    for (int x = 0; x < loaded.cols; ++x) image.at(uint32_t(x), uint32_t(y)) = float(loaded.at<uint16_t>(y, x));
  return image;
}

}  // namespace rt
