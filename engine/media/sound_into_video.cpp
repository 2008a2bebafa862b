#include "media/sound_into_video.h"

#include <gst/gst.h>

#include <algorithm>
#include <chrono>
#include <system_error>
#include <vector>

#include "audio/audio_device.h"
#include "audio/gst_audio.h"
#include "audio/wav_file.h"

namespace rt::media {
namespace {

// Reads `from` and writes it to `to` from `sound_minus_video_us` on the video's clock: its head
// left out or silence put before it, a block at a time (a site's sound may be hours long).
void align_sound(const std::filesystem::path& from, const std::filesystem::path& to, int64_t sound_minus_video_us) {
  constexpr size_t kChannels = audio::kLoudspeakerChannels;
  audio::WavFileInput in(from.string(), int(kChannels));
  audio::WavFileOutput out(to.string(), {}, int(kChannels));
  std::vector<float> block(audio::kBlockSamples * kChannels);
  const int64_t shift = sound_minus_video_us * audio::kSampleRate / 1'000'000;
  for (int64_t silence = shift; silence > 0; silence -= int64_t(audio::kBlockSamples)) {
    std::fill(block.begin(), block.end(), 0.0f);
    out.write(std::span(block).first(size_t(std::min<int64_t>(silence, int64_t(audio::kBlockSamples))) * kChannels));
  }
  for (int64_t skip = -shift; skip > 0; skip -= int64_t(audio::kBlockSamples)) {
    const size_t frames = size_t(std::min<int64_t>(skip, int64_t(audio::kBlockSamples)));
    if (in.read_samples(std::span(block).first(frames * kChannels)) < frames * kChannels) break;
  }
  while (true) {
    const size_t read = in.read_samples(block);
    const size_t n = read - read % kChannels;
    if (n > 0) out.write(std::span(block).first(n));
    if (read < block.size()) break;
  }
  out.finish();
}

}  // namespace

std::string put_sound_into_video(const std::filesystem::path& video, const std::filesystem::path& sound,
                                 int64_t sound_minus_video_us) {
  if (auto missing = audio::missing_audio_elements({"filesrc", "qtdemux", "mpeg4videoparse", "wavparse", "audioconvert", "avenc_aac", "mp4mux", "filesink"});
      !missing.empty())
    return missing;
  const std::filesystem::path aligned = video.parent_path() / (video.stem().string() + ".aligned.wav");
  const std::filesystem::path muxed = video.parent_path() / (video.stem().string() + ".with-sound.mp4");
  std::string error;
  try {
    // FFmpeg's AAC encoder puts 1024 samples of priming before the sound, which mp4mux does not
    // mark to be skipped: the sound starts that much earlier to come out on time.
    constexpr int64_t kAacPrimingUs = 1024 * 1'000'000 / audio::kSampleRate;
    align_sound(sound, aligned, sound_minus_video_us - kAacPrimingUs);
    // The receiver writes MPEG-4 part 2 (OpenCV's mp4v); its parser gives mp4mux the codec data it
    // wants. A parser with pads of its own: parsebin's appear late and lose a race with the data.
    GstElement* pipeline = audio::parse_pipeline(
        "mp4mux name=mux ! filesink name=out  filesrc name=video ! qtdemux name=demux  "
        "demux.video_0 ! queue ! mpeg4videoparse ! mux.  "
        "filesrc name=sound ! wavparse ! audioconvert ! avenc_aac ! queue ! mux.");
    for (const auto& [name, path] : {std::pair{"video", video}, std::pair{"sound", aligned}, std::pair{"out", muxed}}) {
      GstElement* element = gst_bin_get_by_name(GST_BIN(pipeline), name);
      g_object_set(element, "location", path.c_str(), nullptr);
      gst_object_unref(element);
    }
    error = audio::run_to_end(pipeline, std::chrono::minutes(10));
    gst_object_unref(pipeline);
  } catch (const std::exception& e) {
    error = e.what();
  }
  std::error_code ignored;
  std::filesystem::remove(aligned, ignored);
  if (error.empty()) {
    std::filesystem::rename(muxed, video, ignored);
    if (ignored) error = "cannot replace " + video.string() + ": " + ignored.message();
  }
  if (!error.empty()) std::filesystem::remove(muxed, ignored);
  return error;
}

}  // namespace rt::media
