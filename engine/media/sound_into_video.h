#pragma once
// A site's sound put into its video, so that site.mp4 plays as the site was seen and heard: the
// video stream kept as it is, the sound (a WAV) encoded as AAC beside it, starting where it
// started against the video's first frame.
#include <cstdint>
#include <filesystem>
#include <string>

namespace rt::media {

// Rewrites `video` (an MP4 with one video stream) with `sound` as its audio track.
// `sound_minus_video_us`: when the sound's first sample played minus when the video's first frame
// was shown; the sound before the video's start is left out, a gap before the sound's start is
// silence. Empty on success, else what went wrong (the video is then left as it was).
std::string put_sound_into_video(const std::filesystem::path& video, const std::filesystem::path& sound,
                                 int64_t sound_minus_video_us);

}  // namespace rt::media
