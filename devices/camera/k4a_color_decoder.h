#pragma once
// A k4a colour image (MJPG, NV12, YUY2 or BGRA bytes, as a device gives them and a recording
// stores them) decoded into the engine's RGBA image: one decoder for the recordings' reader and
// the live devices, so that a live camera's image is the one its recording would give.
//
// The bytes are checked against the mode before anything is allocated: raw formats must be
// exactly the mode's size, a JPEG no larger than the mode's raw BGRA image and no more pixels.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "camera/k4a_modes.h"
#include "image/host_image.h"

namespace rt::camera::k4a {

// A frame that cannot be decoded; the message starts with the frame's name.
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Where a reader's time went, summed over the captures it decoded (a benchmark's figures): CPU
// time of the decoding thread, so that other work on the machine does not count.
struct DecodeTimes {
  size_t captures = 0;
  double demux_ms = 0;         // reading the blocks of a capture from the file
  double color_decode_ms = 0;  // MJPG to YUV (libavcodec); nothing for raw formats
  double color_convert_ms = 0; // to RGBA (libswscale)
  double to_host_ms = 0;       // into the engine's image: colour bytes to floats, depth byte order
};

// The calling thread's CPU time in milliseconds.
double thread_cpu_ms();

// Empty when `size` bytes can be one colour frame of the mode (exactly its size for a raw format,
// no more than its raw BGRA size for a JPEG); else why not, after `frame_name`.
std::string color_size_problem(ColorFormat format, ColorResolution resolution, size_t size, const std::string& frame_name);

class ColorDecoder {
 public:
  // Throws ImageError when this FFmpeg cannot decode MJPG.
  ColorDecoder(ColorFormat format, ColorResolution resolution);
  ~ColorDecoder();
  ColorDecoder(const ColorDecoder&) = delete;
  ColorDecoder& operator=(const ColorDecoder&) = delete;

  // RGBA8 at the mode's size; throws ImageError starting with `frame_name`.
  HostImage decode(const uint8_t* data, size_t size, const std::string& frame_name, DecodeTimes& times);

 private:
  struct Codec;
  ColorFormat format_;
  ColorResolution resolution_;
  std::unique_ptr<Codec> codec_;
};

}  // namespace rt::camera::k4a
