#pragma once
// A portrait's two video pictures, as the WebRTC link (media/webrtc_peer.h) sends and receives
// them, at the size the call encodes them at now (media/portrait_size_rule.h): the sender scales
// the call's portrait down, the receiver scales what it decoded back to the call's size, so that
// nothing past the link sees another size.
//
// Colour is averaged going down (area) and interpolated coming back (bilinear): it is a picture.
// Depth and alpha are codes (media/depth_alpha_codec.h), resampled by the nearest code both ways
// (media/portrait_size_rule.h, resample_codes_nearest, says why).
#include <gst/gst.h>
#include <gst/video/video.h>

#include <cstdint>
#include <vector>

#include "image/host_image.h"
#include "media/depth_alpha_codec.h"
#include "media/portrait_size_rule.h"

namespace rt::media {

// Sending. The colour picture, I420 (BT.601, as the receiver converts back) at width x height,
// from the portrait's straight-alpha RGBA32F colour.
GstBuffer* make_color_picture(const HostImage& color, uint32_t width, uint32_t height);
// The depth/alpha picture, Y444_10LE: the depth codes in luma, the alpha codes in the first chroma
// plane (0, the edge hard, for a portrait over kSoftEdgeMaxPixels), the second at its neutral middle.
GstBuffer* make_depth_alpha_picture(const HostImage& color, const HostImage& depth, const DepthRange& range,
                                    uint32_t width, uint32_t height);
// An appsrc's caps at another size: x264enc, given them, starts its stream again (a new SPS and a
// keyframe), which the receiver's decoder follows.
void set_picture_size(GstElement* appsrc, uint32_t width, uint32_t height);

// Receiving (check_received_picture_size first). A decoded I420 picture as RGB (3 bytes a pixel)
// at the call's size.
std::vector<uint8_t> rgb_of_color_picture(const GstVideoFrame& frame, uint32_t call_width, uint32_t call_height);
// A decoded Y444_10LE picture's depth and alpha codes at the call's size.
DepthAlphaCodes codes_of_depth_alpha_picture(const GstVideoFrame& frame, uint32_t call_width, uint32_t call_height);

}  // namespace rt::media
