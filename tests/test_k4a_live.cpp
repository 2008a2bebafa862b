// Live k4a cameras (devices/camera/k4a_live_camera.h, k4a_live_site.h) through a fake
// libk4a.so.1.4 (tests/fake_k4a) that serves k4a recordings as connected devices: the live
// backend gives the frame sets and images the recordings' reader gives for the same files; no
// library, no device and an unknown serial are errors saying what to install or plug in; bad
// images from a device are left out and counted, never read; the site file names each camera's
// source.
#include <catch2/catch.hpp>

#include <dlfcn.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "camera/k4a_library.h"
#include "camera/k4a_live_recorder.h"
#include "camera/k4a_live_site.h"
#include "camera/k4a_recording_writer.h"
#include "camera/k4a_site_recordings.h"
#include "camera/k4a_site_writer.h"
#include "camera/site_camera_sources.h"
#include "config/assets.h"
#include "config/json.h"
#include "support/k4a_sites.h"
#include "support/output_dir.h"

using namespace rt;
using namespace rt::camera;
using namespace rt::camera::k4a;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kOutK4aLive = rt::test::output_dir("test_k4a_live");

// The fake library's path, which ctest gives (tests/camera.cmake): the build folder's path kept
// out of the compile line, so that the compiler cache serves every worktree.
std::string fake_k4a_library() {
  const char* path = std::getenv("REMOTETOUCH_TEST_FAKE_K4A");
  if (path == nullptr) FAIL("REMOTETOUCH_TEST_FAKE_K4A names no fake libk4a.so.1.4: run this test through ctest");
  return path;
}
constexpr uint64_t kLiveStartUs = 5'000'000;
constexpr uint64_t kSubordinateDelayUs = 160;

sim::SiteDescription two_camera_site() { return rt::test::k4a_mode_site(2); }

HostImage gradient(uint32_t camera, uint32_t index) {
  HostImage image(1280, 720, PixelFormat::RGBA8);
  for (size_t i = 0; i < image.texels.size(); i += 4) {
    const size_t x = (i / 4) % 1280, y = (i / 4) / 1280;
    image.texels[i] = float((x + 40 * index) % 256) / 255.0f;
    image.texels[i + 1] = float((y + 60 * camera) % 256) / 255.0f;
    image.texels[i + 2] = 0.5f;
    image.texels[i + 3] = 1.0f;
  }
  return image;
}

HostImage live_depth_of(uint32_t camera, uint32_t index) {
  HostImage depth(320, 288, PixelFormat::R16U);
  for (size_t i = 0; i < depth.texels.size(); ++i) depth.texels[i] = float(900 + 300 * camera + index + i % 251);
  return depth;
}

std::string serial_of(size_t camera) { return "fake-00" + std::to_string(camera); }

// A master and a subordinate (its delay 160 us), 5 captures each, the subordinate dropping its
// capture 2; live.json names them as live devices. `standalone`: two standalone devices instead,
// the second's clock `clock_offset_us` ahead. Returns the folder.
std::filesystem::path write_devices(const std::string& name, bool standalone = false, uint64_t clock_offset_us = 0) {
  const std::filesystem::path dir = kOutK4aLive / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  sim::SiteDescription site = two_camera_site();
  for (size_t k = 0; k < site.cameras.size(); ++k) {
    RecordingConfig config = recording_config_for(site.cameras[k], 30, 90);
    config.serial = serial_of(k);
    config.wired_sync = standalone ? WiredSyncMode::standalone : k == 0 ? WiredSyncMode::master : WiredSyncMode::subordinate;
    config.subordinate_delay_ns = k == 0 || standalone ? 0 : kSubordinateDelayUs * 1000;
    config.calibration.color.camera_from_reference.translation() = Eigen::Vector3d(-0.032, 0.001, 0.004);
    RecordingWriter writer(recording_path(dir, site.cameras[k].name), config);
    for (uint32_t i = 0; i < 5; ++i) {
      if (k == 1 && i == 2) continue;
      const uint64_t offset_us = k == 0 ? 0 : standalone ? clock_offset_us : kSubordinateDelayUs;
      writer.write_capture(kLiveStartUs + offset_us + i * 33'333, encode_mjpg(gradient(uint32_t(k), i), 90),
                           live_depth_of(uint32_t(k), i));
    }
    writer.close();
  }
  sim::write_site(dir / "site.json", site);  // the recordings' site: each camera plays <name>.mkv
  for (size_t k = 0; k < site.cameras.size(); ++k) {
    site.cameras[k].source = "k4a";
    site.cameras[k].k4a = {{"serial", serial_of(k)}, {"color_mode", "MJPG_720P"}, {"depth_mode", "NFOV_2X2BINNED"},
                           {"fps", 30}, {"wired_sync", standalone ? "STANDALONE" : k == 0 ? "MASTER" : "SUBORDINATE"},
                           {"subordinate_delay_us", k == 0 || standalone ? 0 : kSubordinateDelayUs}};
  }
  sim::write_site(dir / "live.json", site);
  return dir;
}

// Points the backend at the fake library and the fake's devices at these recordings.
void use_fake(const std::vector<std::filesystem::path>& recordings, const std::string& fault = "",
              const std::filesystem::path& log = {}) {
  ::setenv("REMOTETOUCH_K4A_LIBRARY", fake_k4a_library().c_str(), 1);
  std::string list;
  for (const auto& file : recordings) list += (list.empty() ? "" : ":") + file.string();
  ::setenv("REMOTETOUCH_FAKE_K4A_RECORDINGS", list.c_str(), 1);
  if (fault.empty()) ::unsetenv("REMOTETOUCH_FAKE_K4A_FAULT");
  else ::setenv("REMOTETOUCH_FAKE_K4A_FAULT", fault.c_str(), 1);
  if (log.empty()) ::unsetenv("REMOTETOUCH_FAKE_K4A_LOG");
  else ::setenv("REMOTETOUCH_FAKE_K4A_LOG", log.c_str(), 1);
}

std::vector<std::filesystem::path> recordings_in(const std::filesystem::path& dir) {
  const sim::SiteDescription site = two_camera_site();
  return {recording_path(dir, site.cameras[0].name), recording_path(dir, site.cameras[1].name)};
}

// The captures and images the fake lent and the backend has not given back.
int fake_open_handles() {
  void* handle = dlopen(fake_k4a_library().c_str(), RTLD_NOW | RTLD_NOLOAD);
  if (!handle) return -1;
  const auto count = reinterpret_cast<int (*)()>(dlsym(handle, "fake_k4a_open_handles"));
  const int open = count ? count() : -1;
  dlclose(handle);
  return open;
}

std::unique_ptr<LiveSite> open_live(const std::filesystem::path& site_file) {
  const sim::SiteDescription site = sim::load_site(site_file);
  std::vector<LiveCameraSettings> settings;
  for (const CameraSource& source : camera_sources(site, site_file.parent_path(), site_file.string()))
    settings.push_back(source.live);
  return std::make_unique<LiveSite>(site, settings, nullptr);
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST_CASE("k4a live: through the fake library, the frame sets and images of the recordings' reader") {
  const std::filesystem::path dir = write_devices("same");
  const std::filesystem::path log = dir / "fake.log";
  use_fake(recordings_in(dir), "", log);
  REQUIRE(site_source_kind(sim::load_site(dir / "live.json"), "live.json") == CameraSourceKind::k4a_live);
  SiteRecordings recorded(dir, nullptr);
  {
    std::unique_ptr<LiveSite> live = open_live(dir / "live.json");
    REQUIRE(live->infos().size() == 2);
    for (size_t k = 0; k < 2; ++k) {
      CHECK(live->infos()[k].serial == serial_of(k));
      CHECK(live->intrinsics()[k].color.fx == Approx(recorded.recorded_intrinsics()[k].color.fx).margin(1e-9));
      CHECK(live->intrinsics()[k].depth.cx == Approx(recorded.recorded_intrinsics()[k].depth.cx).margin(1e-9));
      CHECK(live->intrinsics()[k].color_from_depth.isApprox(recorded.recorded_intrinsics()[k].color_from_depth));
      CHECK(live->site().cameras[k].depth.width == 320);
    }
    size_t frames = 0;
    while (std::optional<sim::RgbdFrame> frame = live->next_frame()) {
      const std::optional<sim::RgbdFrame> expected = recorded.next_frame();
      REQUIRE(expected);
      CHECK(frame->timestamp_us == expected->timestamp_us);
      REQUIRE(frame->cameras.size() == 2);
      for (size_t k = 0; k < 2; ++k) {
        INFO("frame set " << frames << ", camera " << k);
        CHECK(frame->cameras[k].camera == expected->cameras[k].camera);
        CHECK(frame->cameras[k].timestamp_us == expected->cameras[k].timestamp_us);
        CHECK(frame->cameras[k].color.width == expected->cameras[k].color.width);
        CHECK(frame->cameras[k].color.texels == expected->cameras[k].color.texels);
        CHECK(frame->cameras[k].depth_mm.texels == expected->cameras[k].depth_mm.texels);
      }
      ++frames;
    }
    CHECK(frames == 5);
    CHECK_FALSE(recorded.next_frame());
    CHECK(live->skipped_captures() == 0);
    CHECK(fake_open_handles() == 0);
  }
  // The subordinate is started first, then the master, in the modes and delay of the site file.
  CHECK(read_text(log) ==
        "start fake-001 color=0 resolution=1 depth=1 fps=2 sync=2 delay=160 synchronized=1\n"
        "start fake-000 color=0 resolution=1 depth=1 fps=2 sync=1 delay=0 synchronized=1\n"
        "stop fake-000\nstop fake-001\n");
}

TEST_CASE("k4a live: standalone devices whose clocks are seconds apart are put together by their first captures") {
  const std::filesystem::path dir = write_devices("standalone", true, 7'000'000);
  use_fake(recordings_in(dir));
  std::unique_ptr<LiveSite> live = open_live(dir / "live.json");
  std::vector<uint64_t> times;
  std::vector<size_t> cameras_in_set;
  while (std::optional<sim::RgbdFrame> frame = live->next_frame()) {
    times.push_back(frame->timestamp_us);
    size_t present = 0;
    for (const sim::RgbdImage& image : frame->cameras)
      present += std::any_of(image.depth_mm.texels.begin(), image.depth_mm.texels.end(), [](float v) { return v != 0; });
    cameras_in_set.push_back(present);
  }
  // Without the rule, 9 sets of one camera each: the second device's times are 7 s later.
  CHECK(cameras_in_set == std::vector<size_t>{2, 2, 1, 2, 2});
  REQUIRE(times.size() == 5);
  CHECK(times[4] - times[0] == 4 * 33'333);
}

TEST_CASE("k4a live: a device that falls silent sits out the sets without holding the others back") {
  const std::filesystem::path dir = write_devices("silent");
  use_fake(recordings_in(dir));
  ::setenv("REMOTETOUCH_FAKE_K4A_SILENT", "fake-001", 1);
  std::unique_ptr<LiveSite> live = open_live(dir / "live.json");
  live->set_timeout_ms(600);
  const auto start = std::chrono::steady_clock::now();
  size_t frames = 0;
  for (; frames < 5; ++frames) {
    const std::optional<sim::RgbdFrame> frame = live->next_frame();
    REQUIRE(frame);
    const HostImage& depth = frame->cameras[1].depth_mm;
    CHECK(std::any_of(depth.texels.begin(), depth.texels.end(), [](float v) { return v != 0; }) == (frames == 0));
  }
  // Waiting the whole 600 ms for it at every set would take 1.8 s at least (2.4 s without polling).
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::milliseconds(1500));
  // The master has ended; the silent one alone is a site without cameras.
  CHECK_THROWS_WITH(live->next_frame(), Contains("no camera gave a capture in 600 ms") && Contains("sync"));
  ::unsetenv("REMOTETOUCH_FAKE_K4A_SILENT");
}

TEST_CASE("k4a live: no library, or not the k4a one, says what to install") {
  ::setenv("REMOTETOUCH_K4A_LIBRARY", "/nonexistent/libk4a.so.1.4", 1);
  CHECK_THROWS_AS(load_k4a_library(), LiveError);
  CHECK_THROWS_WITH(load_k4a_library(), Contains("'/nonexistent/libk4a.so.1.4' could not be loaded") &&
                                            Contains("Azure Kinect SDK") && Contains("Orbbec") &&
                                            Contains("LD_LIBRARY_PATH"));
  ::setenv("REMOTETOUCH_K4A_LIBRARY", "libz.so.1", 1);
  CHECK_THROWS_WITH(load_k4a_library(), Contains("has no function k4a_device_get_installed_count") &&
                                            Contains("not the k4a 1.4 library"));
  ::unsetenv("REMOTETOUCH_K4A_LIBRARY");
  CHECK(k4a_library_name() == "libk4a.so.1.4");
}

TEST_CASE("k4a live: an unknown serial lists the devices found; none connected says to plug one in") {
  const std::filesystem::path dir = write_devices("serials");
  use_fake(recordings_in(dir));
  const std::shared_ptr<const Library> library = load_k4a_library();
  CHECK(connected_serials(*library) == std::vector<std::string>{"fake-000", "fake-001"});
  LiveCameraSettings settings;
  settings.serial = "000123456789";
  settings.depth_mode = DepthMode::nfov_2x2_binned;
  CHECK_THROWS_WITH(LiveCamera(library, settings), Contains("k4a device '000123456789' is not connected") &&
                                                       Contains("'fake-000' 'fake-001'") && Contains("plug in"));
  use_fake({});
  CHECK_THROWS_WITH(LiveCamera(library, settings), Contains("no k4a device is connected") && Contains("USB 3"));
  // A mode the device does not run is its refusal, named.
  use_fake(recordings_in(dir));
  settings.serial = "fake-000";
  settings.depth_mode = DepthMode::wfov_2x2_binned;
  LiveCamera camera(library, settings);
  CHECK_THROWS_WITH(camera.start(), Contains("'fake-000' refused to start in MJPG_720P, WFOV_2X2BINNED at 30 fps"));
}

TEST_CASE("k4a live: a device's bad images are left out and counted, never read") {
  const std::filesystem::path dir = write_devices("bad");
  for (const char* fault : {"1:null-buffer", "1:wrong-size", "1:wrong-stride", "1:ir-format", "1:huge-size", "1:no-depth"}) {
    INFO(fault);
    use_fake(recordings_in(dir), fault);
    {
      std::unique_ptr<LiveSite> live = open_live(dir / "live.json");
      size_t frames = 0, master_images = 0;
      while (std::optional<sim::RgbdFrame> frame = live->next_frame()) {
        ++frames;
        const HostImage& color = frame->cameras[0].color;
        REQUIRE(color.width == 1280);
        if (std::any_of(color.texels.begin(), color.texels.end(), [](float v) { return v != 0.0f; })) ++master_images;
      }
      // Capture 1 of each camera is bad: the master shows 4 of its 5, the subordinate 3 of its 4.
      CHECK(live->skipped_captures() == 2);
      CHECK(master_images == 4);
      CHECK(frames == 4);
      CHECK(fake_open_handles() == 0);  // while the library is loaded: it counts from its loading
    }
  }
}

TEST_CASE("site file: each camera names its source; recordings by path; a mix is refused naming the cameras") {
  const std::filesystem::path dir = write_devices("sources");
  sim::SiteDescription site = sim::load_site(dir / "live.json");
  CHECK(site.cameras[0].source == "k4a");
  CHECK(site.cameras[1].k4a.at("wired_sync") == "SUBORDINATE");

  // Recordings elsewhere, named by path (relative to the site file's folder).
  const std::filesystem::path moved = kOutK4aLive / "sources-moved";
  std::filesystem::remove_all(moved);
  std::filesystem::create_directories(moved / "takes");
  const std::vector<std::filesystem::path> files = recordings_in(dir);
  std::filesystem::copy_file(files[0], moved / "takes" / "a.mkv");
  std::filesystem::copy_file(files[1], moved / "takes" / "b.mkv");
  site.cameras[0].source = "k4a-recording:takes/a.mkv";
  site.cameras[1].source = "k4a-recording:" + (moved / "takes" / "b.mkv").string();
  site.cameras[0].k4a = site.cameras[1].k4a = nlohmann::json::object();
  sim::write_site(moved / "site.json", site);
  SiteRecordings recorded(moved, nullptr);
  CHECK(recorded.frame_count() == 5);
  CHECK(recorded.infos()[1].serial == "fake-001");

  site.cameras[1].source = "k4a";
  site.cameras[1].k4a = {{"serial", "fake-001"}};
  CHECK_THROWS_WITH(site_source_kind(site, "mixed.json"),
                    Contains("mixed.json: the cameras' sources are mixed") && Contains("k4a-recording") &&
                        Contains("k4a (live)") && Contains(site.cameras[1].name));
  sim::write_site(moved / "site.json", site);
  CHECK_THROWS_WITH(SiteRecordings(moved, nullptr), Contains("is a live device") && Contains(site.cameras[1].name));

  // What a site file may say.
  nlohmann::json json = sim::site_to_json(site);
  json["cameras"][0]["source"] = "kinect";
  CHECK_THROWS_WITH(sim::site_from_json(json, "s.json"), Contains("source 'kinect' is none of"));
  json["cameras"][0]["source"] = "k4a";
  json["cameras"][0].erase("k4a");
  CHECK_THROWS_WITH(sim::site_from_json(json, "s.json"), Contains("needs its device's settings in \"k4a\""));
  json["cameras"][0]["k4a"] = {{"serial", "x"}, {"fps", 30}, {"depth_mode", "WFOV_UNBINNED"}};
  CHECK_THROWS_WITH(camera_sources(sim::site_from_json(json, "s.json"), ".", "s.json"), Contains("15 fps at most"));
  json["cameras"][0]["k4a"] = {{"serial", "x"}, {"colour", "MJPG_720P"}};
  CHECK_THROWS_WITH(camera_sources(sim::site_from_json(json, "s.json"), ".", "s.json"), Contains("colour"));
}

TEST_CASE("record: live cameras written as k4a recordings play as the recordings they came from") {
  const std::filesystem::path dir = write_devices("record");
  const std::filesystem::path out = kOutK4aLive / "record-out";
  std::filesystem::remove_all(out);
  use_fake(recordings_in(dir), "3:huge-size");
  const sim::SiteDescription site = sim::load_site(dir / "live.json");
  const RecordSummary summary = record_live_site(site, "live.json", out, 30.0, nullptr);
  // Every device stops at its recording's end, long before 30 s; capture 3 of each was bad.
  CHECK(summary.captures == std::vector<size_t>{4, 3});
  CHECK(summary.skipped == 2);
  SiteRecordings original(dir, nullptr), recorded(out, nullptr);
  CHECK(recorded.infos()[1].serial == "fake-001");
  CHECK(recorded.infos()[1].wired_sync == WiredSyncMode::subordinate);
  CHECK(recorded.infos()[1].subordinate_delay_ns == kSubordinateDelayUs * 1000);
  CHECK(recorded.recorded_intrinsics()[0].color_from_depth.isApprox(original.recorded_intrinsics()[0].color_from_depth));
  // Capture 3 of each device was left out: the master's set 3 and the subordinate's set 4 (it had
  // dropped set 2 already).
  REQUIRE(recorded.frame_count() == 5);
  for (size_t i = 0; i < 5; ++i) {
    const std::optional<sim::RgbdFrame> expected = original.next_frame();
    const std::optional<sim::RgbdFrame> frame = recorded.next_frame();
    REQUIRE(frame);
    CHECK(frame->timestamp_us == expected->timestamp_us);
    for (size_t k = 0; k < 2; ++k) {
      INFO("frame set " << i << ", camera " << k);
      const bool left_out = (k == 0 && i == 3) || (k == 1 && (i == 2 || i == 4));
      const HostImage& depth = frame->cameras[k].depth_mm;
      CHECK(std::all_of(depth.texels.begin(), depth.texels.end(), [](float v) { return v == 0.0f; }) == left_out);
      if (left_out) continue;
      CHECK(frame->cameras[k].color.texels == expected->cameras[k].color.texels);
      CHECK(frame->cameras[k].depth_mm.texels == expected->cameras[k].depth_mm.texels);
    }
  }
  // A folder that holds a site is not written over; a site whose cameras are not all live is refused.
  CHECK_THROWS_WITH(record_live_site(site, "live.json", out, 1.0, nullptr), Contains("holds a site already"));
  sim::SiteDescription mixed = site;
  mixed.cameras[1].source = "simulated";
  mixed.cameras[1].k4a = nlohmann::json::object();
  CHECK_THROWS_WITH(record_live_site(mixed, "mixed.json", kOutK4aLive / "record-mixed", 1.0, nullptr),
                    Contains("mixed.json: live cameras need every camera's source") &&
                        Contains("'" + site.cameras[1].name + "' (simulated) is not live"));
}
