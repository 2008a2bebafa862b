// libFuzzer target: the PNG header check (engine/image/png_header.cpp) that stands before every
// decode of a recorded image. Whatever header it reads must be consistent with the kind checks,
// and an image of a kind the recording uses, small enough to decode here, must decode (through
// the recording's own readers) to exactly the size its header declares, or be refused: the check
// is only a guard if the decoder cannot be made to allocate for another size.
#include "fuzz_target.h"
#include "image/image_io.h"
#include "image/png_header.h"

namespace {

constexpr uint64_t kMostPixelsDecoded = 1 << 16;

rt::fuzz::Outcome png_header(std::string_view input) {
  const std::filesystem::path path = rt::fuzz::work_dir() / "image.png";
  rt::fuzz::write_file(path, input);
  rt::PngHeader header;
  const rt::fuzz::Outcome outcome = rt::fuzz::outcome_of([&] { header = rt::read_png_header(path); });
  if (!outcome.accepted) return outcome;
  if (header.width == 0 || header.height == 0) rt::fuzz::fail("accepted a header of zero size");
  const bool color = header.bit_depth == 8 && (header.color_type == 2 || header.color_type == 6);
  const bool depth = header.bit_depth == 16 && header.color_type == 0;
  for (const rt::PngKind kind : {rt::PngKind::Color8, rt::PngKind::Depth16}) {
    const bool expected = kind == rt::PngKind::Color8 ? color : depth;
    const rt::fuzz::Outcome checked =
        rt::fuzz::outcome_of([&] { rt::check_png_header(path, header.width, header.height, kind); });
    if (checked.accepted != expected) rt::fuzz::fail("the kind check disagrees with the header it read");
    const rt::fuzz::Outcome other_size =
        rt::fuzz::outcome_of([&] { rt::check_png_header(path, header.width + 1, header.height, kind); });
    if (other_size.accepted) rt::fuzz::fail("the size check accepted another width");
  }
  if ((color || depth) && uint64_t(header.width) * header.height <= kMostPixelsDecoded) {
    rt::HostImage image;
    const rt::fuzz::Outcome decoded =
        rt::fuzz::outcome_of([&] { image = color ? rt::read_image(path) : rt::read_depth_png(path); });
    if (decoded.accepted && (image.width != header.width || image.height != header.height))
      rt::fuzz::fail("a PNG whose header says " + std::to_string(header.width) + "x" + std::to_string(header.height) +
                     " decoded to " + std::to_string(image.width) + "x" + std::to_string(image.height));
  }
  return outcome;
}

}  // namespace

RT_FUZZ_TARGET("png_header", png_header)
