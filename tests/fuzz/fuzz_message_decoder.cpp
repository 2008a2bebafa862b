// libFuzzer target: the message decoder on untrusted bytes. It must never crash, hang, leak or
// hit undefined behaviour; every rejection must say why; and whatever it accepts must encode
// again and decode to the same kind of message (the encoder's checks agree with the decoder's).
#include <cstdint>
#include <cstdlib>

#include "net/message_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const rt::net::DecodeResult result = rt::net::decode_message({data, size});
  if (!result.ok()) {
    if (result.error.message.empty()) std::abort();
    return 0;
  }
  const auto again = rt::net::decode_message(rt::net::encode_message(*result.message));
  if (!again.ok() || again.message->index() != result.message->index()) std::abort();
  return 0;
}
