#pragma once
// The pieces of a site's receiver that are plain functions: the frames it writes (names, the
// ground truth as the display would show it, the link-lost notice), what a portrait message says
// about its view and which remote hand it draws.
#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "image/host_image.h"
#include "net/messages.h"
#include "tracking/hand_skeleton.h"

namespace rt::site {

// The notice on a frame shown while the link is down: a user sees why the other person vanished,
// and that it is being dealt with.
void label_link_lost(cv::Mat& bgr, const std::string& reason);

std::string frame_name(uint64_t index);  // frame_NNNN.png

// The simulator's ground truth (rgba8 premultiplied by coverage: the person box-filtered over a
// zero background) over the display's background, as the receiver's composite shows it: linear
// color, no gamma, like shaders/composite.comp.
HostImage truth_over_background(const HostImage& truth, const HostImage& background);

cv::Mat to_bgr8(const HostImage& image);
HostImage from_bgr8(const cv::Mat& bgr);  // rgba8, alpha 1

// The target view a portrait was rendered for, as its message describes it (the sender's frame).
Camera portrait_camera(const net::PortraitMessage& portrait);

}  // namespace rt::site
