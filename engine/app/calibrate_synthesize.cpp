// `remotetouch calibrate synthesize`: a simulated site's calibration inputs with their truth,
// so that the calibration can be tried, and checked, without the hardware.
#include <cstdio>

#include "app/calibrate.h"
#include "calibration/synthetic_site.h"

namespace rt::app {

int run_calibrate_synthesize(const SynthesizeCommandOptions& options) {
  calibration::SyntheticSiteOptions site_options;
  site_options.corner_noise_px = options.corner_noise_px;
  site_options.distance_noise_mm = options.distance_noise_mm;
  site_options.tip_noise_mm = options.tip_noise_mm;
  site_options.tip_outliers = options.tip_outliers;
  site_options.seed = options.seed;
  const calibration::SyntheticSite site = calibration::make_synthetic_site(site_options);
  calibration::write_synthetic_site(site, options.out);
  std::printf("wrote a simulated site to %s: %zu cameras, %zu chessboard views, %zu touches (%zu slipped)\n",
              options.out.c_str(), site.extrinsics_input.cameras.size(), site.extrinsics_input.snapshots.size(),
              site.touches.size(), options.tip_outliers);
  std::printf("calibrate it into a copy of the default site:\n  cp assets/sites/default.json SITE.json\n");
  std::printf("  remotetouch calibrate extrinsics --input %s --site SITE.json\n",
              (options.out / "extrinsics_input.json").c_str());
  std::printf("  remotetouch calibrate tracker --input %s --site SITE.json\n",
              (options.out / "tracker_touches.json").c_str());
  std::printf("the truth: %s, %s\n", (options.out / "truth_site.json").c_str(),
              (options.out / "truth_touch_outliers.json").c_str());
  return 0;
}

}  // namespace rt::app
