#pragma once
// Echo cancellation for the voice: the far user's voice, played by this site's loudspeaker,
// comes back through the room into the microphone; left in, the far user hears themselves a
// round trip later. GStreamer's webrtcdsp (the WebRTC audio processing) removes it, given what the
// loudspeaker played through a webrtcechoprobe; noise suppression and gain control are knobs.
//
// Synchronous, 10 ms at a time: played() a block, then captured() the block recorded while it
// played. The two branches are separate pipelines, each run to completion per block in the
// calling thread (buffers pushed on a pad of our own, no appsrc), so the probe always holds the
// played block before the microphone's block reaches the canceller.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

typedef struct _GstElement GstElement;
typedef struct _GstPad GstPad;

namespace rt::media {

struct EchoCancellerOptions {
  bool noise_suppression = false;
  bool gain_control = false;
};

class EchoCanceller {
 public:
  static constexpr size_t kBlockSamples = 480;  // 10 ms at 48 kHz, mono float

  // Throws std::runtime_error naming the Debian package when webrtcdsp is missing, or what failed.
  explicit EchoCanceller(const EchoCancellerOptions& options = {});
  ~EchoCanceller();
  EchoCanceller(const EchoCanceller&) = delete;
  EchoCanceller& operator=(const EchoCanceller&) = delete;

  // What the loudspeaker plays now: exactly kBlockSamples.
  void played(std::span<const float> block);
  // The microphone's block recorded while the last played block played, without its echo:
  // exactly kBlockSamples in and out.
  std::vector<float> captured(std::span<const float> block);

 private:
  GstElement* far_pipeline_ = nullptr;
  GstPad* far_feed_ = nullptr;
  GstElement* far_sink_ = nullptr;
  GstElement* near_pipeline_ = nullptr;
  GstPad* near_feed_ = nullptr;
  GstElement* near_sink_ = nullptr;
  uint64_t far_samples_ = 0, near_samples_ = 0;
};

// Echo return loss enhancement: how much quieter the echo is after the canceller than in the
// microphone, in dB, over [from, to) samples (10 log10 of the power ratio). The microphone must
// hold echo alone there (the near user silent), as the figure assumes.
double echo_return_loss_enhancement_db(std::span<const float> microphone, std::span<const float> cancelled, size_t from,
                                       size_t to);

}  // namespace rt::media
