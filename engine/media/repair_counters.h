#pragma once
// Retransmission as webrtcbin's own elements count it (media/call_feedback.h reads them).
#include <cstdint>

namespace rt::media {

// Receiving (the jitter buffers): packets asked again (each request, retries included), those whose
// retransmission arrived in time, those given up as lost, and those that came after being given up.
// Sending (rtprtxsend): the packets the other peer asked again and those resent (one no longer in
// the sender's history is asked but not resent).
struct RepairCounters {
  uint64_t retransmissions_asked = 0, retransmissions_arrived = 0, packets_given_up = 0, packets_late = 0;
  uint64_t retransmissions_requested_of_us = 0, retransmissions_sent = 0;
};

}  // namespace rt::media
