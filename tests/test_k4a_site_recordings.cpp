// A site played from k4a recordings (devices/camera/k4a_site_recordings.h, frame_sets.h): the
// cameras' captures grouped into frame sets by time, a dropped or undecodable capture leaving its
// camera out of one set and nothing else, a subordinate's delay taken off, standalone cameras
// put together by their files' start, and the folders that cannot be played refused naming why.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "camera/frame_sets.h"
#include "camera/k4a_recording_writer.h"
#include "camera/k4a_site_recordings.h"
#include "camera/k4a_site_writer.h"
#include "camera/recorded_site.h"
#include "config/assets.h"
#include "config/json.h"
#include "support/k4a_sites.h"
#include "support/output_dir.h"

using namespace rt;
using namespace rt::camera;
using namespace rt::camera::k4a;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kOutK4aSiteRecordings = rt::test::output_dir("test_k4a_site_recordings") / "k4a_site";
constexpr uint64_t kPeriodUsK4aSiteRecordings = 33'333;
constexpr uint64_t kStartUsK4aSiteRecordings = 5'000'000;

// Every capture in exactly one set, at most one per camera, within half a period of the set's
// time, which is its earliest capture's; set times never decrease.
void check_frame_sets(const std::vector<std::vector<uint64_t>>& times, const std::vector<FrameSet>& sets) {
  std::vector<std::vector<int>> used(times.size());
  for (size_t k = 0; k < times.size(); ++k) used[k].assign(times[k].size(), 0);
  uint64_t previous = 0;
  for (const FrameSet& set : sets) {
    REQUIRE(set.captures.size() == times.size());
    CHECK(set.time_us >= previous);
    previous = set.time_us;
    uint64_t earliest = UINT64_MAX;
    for (size_t k = 0; k < times.size(); ++k) {
      if (!set.captures[k]) continue;
      const uint64_t time = times[k].at(*set.captures[k]);
      ++used[k][*set.captures[k]];
      CHECK(time >= set.time_us);
      CHECK(time - set.time_us < (kPeriodUsK4aSiteRecordings + 1) / 2);
      earliest = std::min(earliest, time);
    }
    CHECK(earliest == set.time_us);
  }
  for (size_t k = 0; k < times.size(); ++k)
    for (int count : used[k]) CHECK(count == 1);
}

}  // namespace

TEST_CASE("frame sets: aligned cameras give whole sets; a dropped frame leaves one set without its camera") {
  std::vector<std::vector<uint64_t>> times(3);
  for (uint64_t i = 0; i < 6; ++i)
    for (size_t k = 0; k < 3; ++k)
      if (!(k == 1 && i == 2)) times[k].push_back(kStartUsK4aSiteRecordings + i * kPeriodUsK4aSiteRecordings + k * 150);  // camera 1 drops frame 2
  const std::vector<FrameSet> sets = assemble_frame_sets(times, kPeriodUsK4aSiteRecordings);
  REQUIRE(sets.size() == 6);
  check_frame_sets(times, sets);
  for (size_t i = 0; i < 6; ++i) {
    CHECK(sets[i].time_us == kStartUsK4aSiteRecordings + i * kPeriodUsK4aSiteRecordings);
    CHECK(sets[i].captures[0] == i);
    CHECK(sets[i].captures[1].has_value() == (i != 2));
    CHECK(sets[i].captures[2] == i);
  }
  CHECK(sets[3].captures[1] == 2u);  // the file's next capture, not a shifted one
}

TEST_CASE("frame sets: half a period apart is another set; a camera with no captures never holds one back") {
  const std::vector<std::vector<uint64_t>> split = {{1000}, {1000 + (kPeriodUsK4aSiteRecordings + 1) / 2}};
  CHECK(assemble_frame_sets(split, kPeriodUsK4aSiteRecordings).size() == 2);
  const std::vector<std::vector<uint64_t>> together = {{1000}, {1000 + (kPeriodUsK4aSiteRecordings + 1) / 2 - 1}};
  CHECK(assemble_frame_sets(together, kPeriodUsK4aSiteRecordings).size() == 1);
  const std::vector<std::vector<uint64_t>> silent = {{1000, 1000 + kPeriodUsK4aSiteRecordings}, {}};
  const std::vector<FrameSet> sets = assemble_frame_sets(silent, kPeriodUsK4aSiteRecordings);
  REQUIRE(sets.size() == 2);
  CHECK_FALSE(sets[0].captures[1]);
  CHECK(assemble_frame_sets({}, kPeriodUsK4aSiteRecordings).empty());
}

TEST_CASE("frame sets: random jitter and drops keep every capture once, within half a period") {
  std::mt19937 random(7);
  for (int trial = 0; trial < 50; ++trial) {
    const size_t cameras = 1 + random() % 6;
    std::vector<std::vector<uint64_t>> times(cameras);
    for (size_t k = 0; k < cameras; ++k) {
      uint64_t time = kStartUsK4aSiteRecordings + random() % 40'000;
      for (int i = 0; i < 40; ++i) {
        time += kPeriodUsK4aSiteRecordings - 2'000 + random() % 4'000 + (random() % 10 == 0 ? kPeriodUsK4aSiteRecordings : 0);  // jitter, drops
        if (random() % 7 != 0) times[k].push_back(time);
      }
    }
    check_frame_sets(times, assemble_frame_sets(times, kPeriodUsK4aSiteRecordings));
  }
}

namespace {

sim::SiteDescription test_site(size_t cameras) { return rt::test::k4a_mode_site(cameras); }

HostImage flat_color(float level) {
  HostImage image(1280, 720, PixelFormat::RGBA8, level);
  for (size_t i = 3; i < image.texels.size(); i += 4) image.texels[i] = 1.0f;
  return image;
}

HostImage depth_of(uint32_t camera, uint32_t index) {
  HostImage depth(320, 288, PixelFormat::R16U);
  for (size_t i = 0; i < depth.texels.size(); ++i) depth.texels[i] = float(1000 + 100 * camera + index + i % 7);
  return depth;
}

struct CameraPlan {
  WiredSyncMode sync = WiredSyncMode::standalone;
  uint64_t subordinate_delay_us = 0;
  uint64_t clock_offset_us = 0;  // the device's clock against the others'
  uint32_t fps = 30;
  int64_t depth_delay_us = 0;
  bool color_from_depth_identity = true;
  std::vector<uint32_t> dropped, corrupt;  // capture indices
};

// Writes site.json and one recording per camera: capture i of camera k at i periods.
std::filesystem::path write_site(const std::string& name, const std::vector<CameraPlan>& plans, uint32_t captures = 5) {
  const std::filesystem::path dir = kOutK4aSiteRecordings / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const sim::SiteDescription site = test_site(plans.size());
  sim::write_site(dir / "site.json", site);
  for (size_t k = 0; k < plans.size(); ++k) {
    const CameraPlan& plan = plans[k];
    RecordingConfig config = recording_config_for(site.cameras[k], plan.fps, 90);
    config.wired_sync = plan.sync;
    config.subordinate_delay_ns = plan.subordinate_delay_us * 1000;
    config.depth_delay_ns = plan.depth_delay_us * 1000;
    if (!plan.color_from_depth_identity)
      config.calibration.color.camera_from_reference.translation() = Eigen::Vector3d(-0.032, 0, 0);
    RecordingWriter writer(recording_path(dir, site.cameras[k].name), config);
    const uint64_t period_us = 1'000'000 / plan.fps;
    for (uint32_t i = 0; i < captures; ++i) {
      if (std::count(plan.dropped.begin(), plan.dropped.end(), i)) continue;
      const bool corrupt = std::count(plan.corrupt.begin(), plan.corrupt.end(), i) > 0;
      const std::vector<uint8_t> jpeg = corrupt ? std::vector<uint8_t>(600, 0x5a) : encode_mjpg(flat_color(0.1f * k + 0.02f * i), 90);
      writer.write_capture(kStartUsK4aSiteRecordings + plan.clock_offset_us + plan.subordinate_delay_us + i * period_us, jpeg,
                           depth_of(uint32_t(k), i));
    }
    writer.close();
  }
  return dir;
}

bool all_zero(const HostImage& image) {
  return std::all_of(image.texels.begin(), image.texels.end(), [](float v) { return v == 0.0f; });
}

}  // namespace

TEST_CASE("k4a site: a subordinate's delay taken off, a dropped and a corrupt capture each leave one set") {
  CameraPlan master, subordinate;
  master.sync = WiredSyncMode::master;
  subordinate.sync = WiredSyncMode::subordinate;
  subordinate.subordinate_delay_us = 160;
  subordinate.dropped = {2};
  subordinate.corrupt = {3};
  const std::filesystem::path dir = write_site("sync", {master, subordinate});
  REQUIRE(is_site_of_recordings(dir));
  SiteRecordings site(dir, nullptr);
  CHECK(site.clock_description() == "device time");
  REQUIRE(site.frame_count() == 5);
  CHECK(site.site().cameras.size() == 2);
  CHECK(site.recorded_intrinsics()[1].depth.width == 320);
  CHECK(std::abs(site.recorded_intrinsics()[0].color.fx - 610) < 1e-6);
  for (size_t i = 0; i < 5; ++i) {
    CHECK(site.frame_timestamp_us(i) == kStartUsK4aSiteRecordings + i * kPeriodUsK4aSiteRecordings);
    const std::optional<sim::RgbdFrame> frame = site.next_frame();
    REQUIRE(frame);
    REQUIRE(frame->cameras.size() == 2);
    CHECK(frame->cameras[0].depth_mm.texels == depth_of(0, uint32_t(i)).texels);
    const sim::RgbdImage& second = frame->cameras[1];
    REQUIRE(second.color.width == 1280);
    REQUIRE(second.depth_mm.width == 320);
    if (i == 2 || i == 3) {
      CHECK(all_zero(second.depth_mm));  // no surface: the other camera renders the user
      CHECK(all_zero(second.color));
    } else {
      CHECK(second.depth_mm.texels == depth_of(1, uint32_t(i)).texels);
      CHECK(std::abs(second.color.at(10, 10, 0) - (0.1f + 0.02f * i)) < 2.0f / 255);
      CHECK(second.timestamp_us == kStartUsK4aSiteRecordings + i * kPeriodUsK4aSiteRecordings);  // the delay taken off
    }
  }
  CHECK_FALSE(site.next_frame());
  CHECK(site.skipped_captures() == 1);  // the corrupt one; the dropped one was never written
  // Back to an earlier set: the files are read again from their start.
  site.seek(1);
  CHECK(site.next_frame()->cameras[1].depth_mm.texels == depth_of(1, 1).texels);
  site.seek(4);
  CHECK(site.next_frame()->cameras[1].depth_mm.texels == depth_of(1, 4).texels);
  CHECK_THROWS(site.seek(6));
}

TEST_CASE("k4a site: standalone cameras whose clocks differ are put together by their files' start") {
  CameraPlan first, second;
  second.clock_offset_us = 3'600'000'000;  // an hour apart
  SiteRecordings site(write_site("standalone", {first, second}, 3), nullptr);
  CHECK_THAT(site.clock_description(), Contains("since each recording's start"));
  REQUIRE(site.frame_count() == 3);
  for (size_t i = 0; i < 3; ++i) {
    const sim::RgbdFrame frame = *site.next_frame();
    CHECK(frame.cameras[0].depth_mm.texels == depth_of(0, uint32_t(i)).texels);
    CHECK(frame.cameras[1].depth_mm.texels == depth_of(1, uint32_t(i)).texels);
  }
}

TEST_CASE("k4a site: a device whose colour lens is apart from its depth lens says where, for registration") {
  CameraPlan offset;
  offset.color_from_depth_identity = false;
  SiteRecordings site(write_site("offset", {CameraPlan{}, offset}), nullptr);
  CHECK(site.recorded_intrinsics()[0].color_from_depth.isApprox(Eigen::Isometry3d::Identity()));
  CHECK(site.recorded_intrinsics()[1].color_from_depth.translation().isApprox(Eigen::Vector3d(-0.032, 0, 0)));
}

TEST_CASE("k4a site: a colour lens calibrated by hand replaces the factory's where the site file says so") {
  const std::filesystem::path dir = write_site("lens", {CameraPlan{}, CameraPlan{}});
  sim::SiteDescription described = sim::load_site(dir / "site.json");
  described.cameras[1].color.fx = described.cameras[1].color.fy = 700.0;
  described.cameras[1].color.distortion.p1 = 0.001;
  described.cameras[1].color_lens_from_site_file = true;
  described.cameras[0].color.fx = 800.0;  // not asked for: the factory's stays
  sim::write_site(dir / "site.json", described);
  REQUIRE(sim::load_site(dir / "site.json").cameras[1].color_lens_from_site_file);
  {
    SiteRecordings site(dir, nullptr);
    CHECK(site.recorded_intrinsics()[0].color.fx == Approx(610.0).epsilon(1e-6));
    CHECK(site.site().cameras[0].color.fx == Approx(610.0).epsilon(1e-6));
    CHECK(site.recorded_intrinsics()[1].color.fx == 700.0);
    CHECK(site.recorded_intrinsics()[1].color.distortion.p1 == 0.001);
    CHECK(site.site().cameras[1].color.fx == 700.0);
  }
  described.cameras[1].color = scaled_intrinsics(described.cameras[1].color, 0.5);
  sim::write_site(dir / "site.json", described);
  CHECK_THROWS_WITH(SiteRecordings(dir, nullptr), Contains("site-file") && Contains("640x360") && Contains("1280x720"));

  nlohmann::json json = config::read_json_file(dir / "site.json");
  json["cameras"][0]["color_lens"] = "calibrated";
  config::write_json_file(dir / "site.json", json);
  CHECK_THROWS_WITH(sim::load_site(dir / "site.json"), Contains("color_lens 'calibrated'"));
}

TEST_CASE("k4a site: depth taken after colour is reported, once per camera") {
  CameraPlan late;
  late.depth_delay_us = 200;
  char* text = nullptr;
  size_t size = 0;
  std::FILE* log = open_memstream(&text, &size);
  REQUIRE(log);
  {
    SiteRecordings site(write_site("late", {CameraPlan{}, late}, 3), log);
    CHECK(site.frame_count() == 3);
  }
  std::fclose(log);
  const std::string logged(text, size);
  std::free(text);
  CHECK_THAT(logged, Contains("depth is taken 200 us after colour (K4A_DEPTH_DELAY_NS)"));
  CHECK(logged.find("K4A_DEPTH_DELAY_NS") == logged.rfind("K4A_DEPTH_DELAY_NS"));  // the delayed camera only
}

TEST_CASE("k4a site: a recording cut short plays up to its cut, the others to their end") {
  const std::filesystem::path dir = write_site("truncated", {CameraPlan{}, CameraPlan{}}, 6);
  const std::filesystem::path cut = recording_path(dir, test_site(2).cameras[1].name);
  std::filesystem::resize_file(cut, std::filesystem::file_size(cut) * 2 / 3);
  char* text = nullptr;
  size_t size = 0;
  std::FILE* log = open_memstream(&text, &size);
  REQUIRE(log);
  size_t with_second = 0, sets = 0;
  {
    SiteRecordings site(dir, log);
    sets = site.frame_count();
    while (const std::optional<sim::RgbdFrame> frame = site.next_frame())
      with_second += !all_zero(frame->cameras[1].depth_mm);
  }
  std::fclose(log);
  const std::string logged(text, size);
  std::free(text);
  CHECK(sets == 6);  // the whole camera sets the pace
  CHECK(with_second >= 1);
  CHECK(with_second < 6);
  CHECK_THAT(logged, Contains(cut.string()) && (Contains("truncated") || Contains("damaged")));
}

TEST_CASE("k4a site: folders that cannot be played are refused naming what is wrong") {
  SECTION("a camera without its recording") {
    const std::filesystem::path dir = write_site("missing", {CameraPlan{}, CameraPlan{}});
    const sim::SiteDescription site = test_site(2);
    std::filesystem::remove(recording_path(dir, site.cameras[1].name));
    CHECK_THROWS_WITH(SiteRecordings(dir, nullptr), Contains(site.cameras[1].name) && Contains("has no recording"));
  }
  SECTION("cameras at different rates") {
    CameraPlan slow;
    slow.fps = 15;
    CHECK_THROWS_WITH(SiteRecordings(write_site("rates", {CameraPlan{}, slow}), nullptr),
                      Contains("15 fps") && Contains("one rate"));
  }
  SECTION("a camera with no capture") {
    const std::filesystem::path dir = write_site("silent", {CameraPlan{}, CameraPlan{}});
    const sim::SiteDescription site = test_site(2);
    const CameraPlan plan;
    RecordingWriter(recording_path(dir, site.cameras[1].name), recording_config_for(site.cameras[1], plan.fps, 90)).close();
    CHECK_THROWS_WITH(SiteRecordings(dir, nullptr), Contains(site.cameras[1].name + ".mkv"));
  }
  SECTION("no recording format at all") {
    const std::filesystem::path dir = kOutK4aSiteRecordings / "empty";
    std::filesystem::create_directories(dir);
    CHECK_THROWS_WITH(open_recorded_site(dir), Contains("neither a calibration.json") && Contains("site.json"));
    CHECK_THROWS_WITH(open_recorded_site(kOutK4aSiteRecordings / "nowhere"), Contains("does not exist"));
  }
}
