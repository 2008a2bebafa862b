// libFuzzer target: a site's --config file (engine/site/site_config.cpp) from untrusted text. It is
// written to a file, as `remotetouch site --config FILE` reads it; whatever is accepted must leave
// the options within the ranges the config's fields allow.
#include "fuzz_target.h"
#include "site/site_options.h"

namespace {

rt::fuzz::Outcome site_config(std::string_view input) {
  const std::filesystem::path path = rt::fuzz::work_dir() / "site.json";
  rt::fuzz::write_file(path, input);
  rt::site::SiteRunOptions options;
  const rt::fuzz::Outcome outcome = rt::fuzz::outcome_of([&] { rt::site::apply_site_config(path, options); });
  if (outcome.accepted) {
    if (options.run.width != 0 && (options.run.width < 16 || options.run.width > 4096))
      rt::fuzz::fail("accepted a width of " + std::to_string(options.run.width));
    if (options.run.height != 0 && (options.run.height < 16 || options.run.height > 4096))
      rt::fuzz::fail("accepted a height of " + std::to_string(options.run.height));
    // 0: not given, chosen by the device when the site starts.
    if (!(options.time_scale == 0.0 || (options.time_scale >= 1e-3 && options.time_scale <= 10.0)))
      rt::fuzz::fail("accepted a time scale of " + std::to_string(options.time_scale));
    if (!(options.resolution_scale >= 0.0 && options.resolution_scale <= 1.0))
      rt::fuzz::fail("accepted a resolution scale of " + std::to_string(options.resolution_scale));
    if (options.frames_given && options.run.frames < 1) rt::fuzz::fail("accepted 0 frames");
    if (options.motor != "simulated" && options.motor != "usb" && options.motor != "auto")
      rt::fuzz::fail("accepted the motor '" + options.motor + "'");
  }
  return outcome;
}

}  // namespace

RT_FUZZ_TARGET("site_config", site_config)
