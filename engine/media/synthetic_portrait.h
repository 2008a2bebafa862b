#pragma once
// A portrait shaped like the sender's (head, shoulders and a raised forearm with straight-alpha
// edges, smooth colour with some texture and camera noise, the depth of a rounded body 1.1-1.5 m
// away with 1 mm sensor noise, nothing around it) for the WebRTC link's test and benchmark. Its
// silhouette sways from frame to frame, so a video codec meets motion, not a still image.
#include <cstdint>

#include "net/messages.h"

namespace rt::media {

net::PortraitMessage synthetic_portrait(uint32_t width, uint32_t height, uint64_t frame);

}  // namespace rt::media
