// A site's inputs (engine/app/site_inputs.h, site_eye.h, site_motor.h): replay pacing on the
// scene clock, the paced tracker, the camera choice from tracked hands, the eye's fallback to the
// seat, the motor choice, and a recording's checks before a site connects.
#include <catch2/catch.hpp>


#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include "site/site_display.h"
#include "site/site_eye.h"
#include "site/site_inputs.h"
#include "site/site_motor.h"
#include "site/site_run.h"
#include "pipeline/site_simulator.h"
#include "config/json.h"
#include "image/image_io.h"
#include "sim/default_site.h"
#include "sim/recording.h"
#include "support/gpu_test.h"
#include "support/hands.h"

using namespace rt;
using Catch::Contains;

namespace {

const std::filesystem::path kOutSiteInputs = std::filesystem::path("test-out") / "site_inputs";

std::filesystem::path fresh_dir_site_inputs(const std::string& name) {
  const std::filesystem::path dir = kOutSiteInputs / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

class ListTracker : public sim::HandTracker {
 public:
  explicit ListTracker(std::vector<sim::TrackerFrame> frames) : frames_(frames.begin(), frames.end()) {}
  std::optional<sim::TrackerFrame> next_frame() override {
    if (frames_.empty()) return std::nullopt;
    sim::TrackerFrame frame = frames_.front();
    frames_.pop_front();
    return frame;
  }

 private:
  std::deque<sim::TrackerFrame> frames_;
};

sim::TrackerFrame tracker_frame(uint64_t timestamp_us, double palm_y_mm) {
  sim::TrackerFrame frame;
  frame.timestamp_us = timestamp_us;
  sim::TrackerHand hand;
  hand.palm_position = Eigen::Vector3d(0, palm_y_mm, 0);
  frame.hands.push_back(hand);
  return frame;
}

HandSkeleton hand_at(bool is_left, double z) {
  HandSkeleton hand = test::flat_hand(is_left ? -0.1 : 0.1, 0.0, z);
  hand.is_left = is_left;
  return hand;
}

EyePair eyes_at(const Eigen::Vector3d& midpoint) {
  EyePair pair;
  pair.midpoint = midpoint;
  pair.viewer_right = midpoint + Eigen::Vector3d(0.032, 0, 0);
  pair.viewer_left = midpoint - Eigen::Vector3d(0.032, 0, 0);
  return pair;
}

EyePair no_face() {
  EyePair pair;
  pair.failure = ViewerFailure::EyesNotFound;
  pair.message = "the eyes were found in 0 view(s), at least 2 are needed; camera 'c0': no frontal face in the image";
  return pair;
}

// How a recording's calibration.json gives the cameras' sizes: the intrinsics at the recorded
// size (as `simulate` writes them), or at the calibrated size with the scale stated beside them,
// or at the calibrated size with nothing said (which a reader must refuse, not guess).
enum class CalibrationSizes { Recorded, ScaleStated, Unstated };
constexpr double kRecordedScale = 0.02;

// A tiny recording of the default site: `frames` frames at 1/50 of the cameras' resolution.
std::filesystem::path write_recording_site_inputs(const std::string& name, int frames = 3,
                                      CalibrationSizes sizes = CalibrationSizes::Recorded) {
  const std::filesystem::path dir = fresh_dir_site_inputs(name);
  const sim::SiteDescription site = sim::make_default_site();
  sim::SiteDescription recorded = site;
  for (auto& camera : recorded.cameras) {
    camera.color = scaled_intrinsics(camera.color, kRecordedScale);
    camera.depth = scaled_intrinsics(camera.depth, kRecordedScale);
  }
  nlohmann::json calibration = sim::site_to_json(sizes == CalibrationSizes::Recorded ? recorded : site);
  if (sizes == CalibrationSizes::ScaleStated) calibration["recorded_scale"] = kRecordedScale;
  sim::RecordingWriter writer(dir, calibration);
  for (int i = 0; i < frames; ++i) {
    sim::RgbdFrame frame;
    frame.index = uint64_t(i);
    frame.timestamp_us = 1'000'000 + uint64_t(i) * 33'333;
    for (const auto& camera : site.cameras) {
      const CameraIntrinsics color = scaled_intrinsics(camera.color, kRecordedScale);
      const CameraIntrinsics depth = scaled_intrinsics(camera.depth, kRecordedScale);
      sim::RgbdImage image;
      image.camera = camera.name;
      image.timestamp_us = frame.timestamp_us;
      image.color = HostImage(color.width, color.height, PixelFormat::RGBA8, 0.5f);
      image.depth_mm = HostImage(depth.width, depth.height, PixelFormat::R16U, 700.0f);
      frame.cameras.push_back(image);
    }
    writer.write_frame(frame);
  }
  std::ofstream(dir / "tracker.jsonl") << "";
  return dir;
}

}  // namespace

TEST_CASE("replay pacing: the newest recorded frame whose time has come, stale ones skipped", "[site_inputs]") {
  const site::ReplayPacing pacing({5'000'000, 5'033'000, 5'066'000, 5'200'000});
  CHECK_FALSE(pacing.due_at(-0.001));
  CHECK(pacing.due_at(0.0) == 0u);
  CHECK(pacing.due_at(0.0329) == 0u);
  CHECK(pacing.due_at(0.033) == 1u);
  CHECK(pacing.due_at(0.150) == 2u);  // a late caller skips nothing it can still show
  CHECK(pacing.due_at(0.5) == 3u);    // and frame 1 and 2 are skipped when later than that
  CHECK(pacing.time_s(3) == Approx(0.2));
  CHECK(pacing.fps(30.0) == Approx(3 / 0.2));
  CHECK(pacing.duration_s(30.0) == Approx(0.2 + 0.2 / 3));
  CHECK(site::ReplayPacing({7}).fps(25.0) == 25.0);
  CHECK_THROWS_WITH(site::ReplayPacing({10, 20, 15}), Contains("frame 2") && Contains("before the previous"));
  CHECK_THROWS_AS(site::ReplayPacing({}), std::invalid_argument);
}

TEST_CASE("paced tracker: frames on the scene clock, in the site frame, the last one standing", "[site_inputs]") {
  sim::TrackerPlacement placement;
  placement.site_from_tracker.translation() = Eigen::Vector3d(0.0, -0.2, 0.1);
  site::PacedHandTracker tracker(
      std::make_unique<ListTracker>(std::vector{tracker_frame(990'000, 100), tracker_frame(1'010'000, 200),
                                                tracker_frame(1'030'000, 300)}),
      placement, 1'000'000);
  // The first frame is 10 ms before the origin: due at once.
  auto hands = tracker.at(0.0);
  REQUIRE(hands);
  CHECK(hands->time_s == Approx(-0.01));
  REQUIRE(hands->hands.size() == 1);
  CHECK(hands->hands[0].palm.y() == Approx(-0.2 + 0.1));
  hands = tracker.at(0.0299);
  CHECK(hands->time_s == Approx(0.01));
  CHECK(hands->hands[0].palm.y() == Approx(0.0));
  hands = tracker.at(10.0);
  CHECK(hands->time_s == Approx(0.03));
  CHECK(tracker.at(20.0)->hands[0].palm.y() == Approx(0.1));

  site::PacedHandTracker late(std::make_unique<ListTracker>(std::vector{tracker_frame(50'000, 100)}), placement, 0);
  CHECK_FALSE(late.at(0.049));
  CHECK(late.at(0.05));
}

TEST_CASE("camera choice: the tracked hand nearest the glass, whichever hands are tracked", "[site_inputs]") {
  using ibr::TouchingHand;
  CHECK(site::touching_side({hand_at(false, 0.3), hand_at(true, 0.1)}) == TouchingHand::Left);
  CHECK(site::touching_side({hand_at(false, 0.1), hand_at(true, 0.3)}) == TouchingHand::Right);
  CHECK(site::touching_side({hand_at(true, 0.4)}) == TouchingHand::Left);  // the right hand is not tracked
  CHECK(site::touching_side({hand_at(false, 0.4)}) == TouchingHand::Right);
  CHECK(site::touching_side({}) == TouchingHand::Right);
  HandSkeleton lost = hand_at(true, 0.1);
  lost.palm.z() = NAN;
  CHECK(site::touching_side({hand_at(false, 0.5), lost}) == TouchingHand::Right);

  site::TrackedHandsHistory history;
  CHECK_FALSE(history.closest(1.0));
  history.add(1.00, {hand_at(false, 0.1)});
  history.add(1.02, {hand_at(true, 0.1)});
  CHECK(history.closest(1.009)->at(0).is_left == false);
  CHECK(history.closest(1.011)->at(0).is_left == true);
  history.add(3.5, {});  // more than two seconds on: the old entries go
  CHECK(history.closest(1.0)->empty());
}

TEST_CASE("eye search: the cameras' eye once enough frames agree", "[site_inputs][eye]") {
  site::EyeSearch search;
  const Eigen::Vector3d seat(0, 0.1, 0.7), truth(0.01, 0.12, 0.68);
  for (int i = 0; i < 14; ++i) CHECK(search.add(uint64_t(i), eyes_at(truth + Eigen::Vector3d(0, 0, 0.001 * (i % 3)))) ==
                                     site::EyeSearch::State::Searching);
  CHECK(search.eye_or(seat) == seat);  // the seat stands in until found
  CHECK_THAT(search.source(), Catch::StartsWith("seat (searching"));
  CHECK(search.add(14, eyes_at(truth)) == site::EyeSearch::State::Found);
  CHECK((search.eye_or(seat) - truth).norm() < 0.002);
  CHECK_THAT(search.source(), Catch::StartsWith("cameras (15 frames, spread"));
  // Decided once: later frames change nothing.
  CHECK(search.add(15, no_face()) == site::EyeSearch::State::Found);
}

TEST_CASE("eye search: no face in the bounded number of frames falls back to the seat, saying why", "[site_inputs][eye]") {
  site::EyeSearchOptions options;
  options.max_frames = 20;
  site::EyeSearch search(options);
  for (int i = 0; i < 19; ++i) CHECK(search.add(uint64_t(i), no_face()) == site::EyeSearch::State::Searching);
  CHECK(search.add(19, no_face()) == site::EyeSearch::State::GaveUp);
  const Eigen::Vector3d seat(0, 0.1, 0.7);
  CHECK(search.eye_or(seat) == seat);
  CHECK(search.source() ==
        "seat (no face found in 20 frames: the eyes were found in 0 view(s), at least 2 are needed; camera 'c0': no "
        "frontal face in the image)");

  // Eyes seen, but they do not agree (a moving viewer, wrong detections): the seat too.
  site::EyeSearch wobbly(options);
  for (int i = 0; i < 20; ++i) wobbly.add(uint64_t(i), eyes_at(Eigen::Vector3d(0.1 * (i % 4), 0.1, 0.7)));
  CHECK(wobbly.state() == site::EyeSearch::State::GaveUp);
  CHECK_THAT(wobbly.source(), Catch::StartsWith("seat (no steady viewpoint in 20 frames: "));

  site::EyeSearch no_detector;
  no_detector.give_up("the eye detector cannot start: cascade missing");
  CHECK(no_detector.source() == "seat (the eye detector cannot start: cascade missing)");
  options.max_frames = 3;
  CHECK_THROWS_WITH(site::EyeSearch(options), Contains("max_frames"));
}

TEST_CASE("eye finder: a thread over offered frames, deciding once", "[site_inputs][eye]") {
  // Grey images hold no face: after max_frames offered frame sets the seat stands.
  const sim::SiteDescription site = sim::make_default_site();
  std::vector<Camera> cameras;
  for (const auto& camera : site.cameras) {
    Camera color = camera.color_camera();
    color.intrinsics = scaled_intrinsics(camera.color, 0.1);
    cameras.push_back(color);
  }
  std::vector<sim::RgbdImage> images(cameras.size());
  for (size_t k = 0; k < cameras.size(); ++k)
    images[k].color = HostImage(cameras[k].intrinsics.width, cameras[k].intrinsics.height, PixelFormat::RGBA8, 0.4f);
  site::EyeSearchOptions options;
  options.max_frames = options.viewpoint.frames_needed;
  std::vector<std::string> decided;
  std::mutex decided_mutex;
  site::ViewerEyeFinder finder(cameras, site.seat.head_centre_m, options, [&](const std::string& source) {
    std::lock_guard lock(decided_mutex);
    decided.push_back(source);
  });
  for (int i = 0; i < 2000 && !finder.decided(); ++i) {
    if (finder.wants_frame()) finder.offer(uint64_t(i), images);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  REQUIRE(finder.decided());
  CHECK_FALSE(finder.wants_frame());
  CHECK(finder.eye() == site.seat.head_centre_m);
  CHECK_THAT(finder.source(), Catch::StartsWith("seat (no face found in 15 frames: "));
  std::lock_guard lock(decided_mutex);
  CHECK(decided == std::vector<std::string>{finder.source()});
}

TEST_CASE("motor choice: the board when attached, else the simulated motor, saying which", "[site_inputs][motor]") {
  using site::MotorMode;
  const std::vector<motor::UsbBoard> none;
  const std::vector<motor::UsbBoard> one = {{1, 4, "1-2"}};
  const std::vector<motor::UsbBoard> two = {{1, 4, "1-2"}, {3, 7, "3-1.4"}};

  auto decision = site::decide_motor(MotorMode::Auto, none);
  CHECK_FALSE(decision.use_usb);
  CHECK(decision.error.empty());
  CHECK(decision.description == "simulated: no Arduino Uno 2341:0043 found");

  decision = site::decide_motor(MotorMode::Auto, one);
  CHECK(decision.use_usb);
  CHECK(decision.description == "usb (bus 1 port 1-2 (address 4), 2341:0043)");
  decision = site::decide_motor(MotorMode::Auto, two);
  CHECK_THAT(decision.description, Contains("bus 1 port 1-2") && Contains("2 such boards"));

  decision = site::decide_motor(MotorMode::Usb, none);
  CHECK_FALSE(decision.use_usb);
  CHECK(decision.error == "--motor usb: no Arduino Uno 2341:0043 found on USB; plug in the motor's board or use --motor simulated");
  decision = site::decide_motor(MotorMode::Auto, std::string("cannot list USB devices: LIBUSB_ERROR_IO"));
  CHECK(decision.description == "simulated: no Arduino Uno 2341:0043 found (cannot list USB devices: LIBUSB_ERROR_IO)");
  CHECK_FALSE(site::decide_motor(MotorMode::Usb, std::string("no USB")).error.empty());

  decision = site::decide_motor(MotorMode::Simulated, one);  // asked for: the board stays unused
  CHECK_FALSE(decision.use_usb);
  CHECK(decision.description == "simulated (--motor simulated)");

  CHECK(site::parse_motor_mode("auto") == MotorMode::Auto);
  CHECK(site::parse_motor_mode("usb") == MotorMode::Usb);
  CHECK_THROWS_WITH(site::parse_motor_mode("serial"), Contains("simulated, usb or auto"));
  CHECK(site::open_site_motor(MotorMode::Simulated, {}).motor != nullptr);
}

TEST_CASE("a recording for replay: cameras at the images' size, ground truth where recorded", "[site_inputs][replay]") {
  const std::filesystem::path dir = write_recording_site_inputs("good");
  site::SiteReplay replay(dir, 0, 4);
  CHECK(replay.frame_count() == 3);
  CHECK(replay.origin_us() == 1'000'000);
  CHECK(replay.pacing().time_s(2) == Approx(0.066666));
  REQUIRE(replay.cameras().size() == 6);
  const sim::RgbdFrame frame = replay.read(1);
  CHECK(frame.index == 1);
  CHECK(replay.cameras()[0].color.intrinsics.width == frame.cameras[0].color.width);
  CHECK(replay.cameras()[0].depth.intrinsics.height == frame.cameras[0].depth_mm.height);
  CHECK_FALSE(replay.ground_truth(1));
  write_image(sim::ground_truth_color_path(dir, 1), HostImage(8, 6, PixelFormat::RGBA8, 1.0f));
  CHECK(replay.ground_truth(1)->width == 8);
  CHECK(site::SiteReplay(dir, 2, 4).frame_count() == 2);  // --frames plays fewer
}

TEST_CASE("a recording's calibration gives the recorded sizes, or states the scale: nothing is guessed", "[site_inputs][replay]") {
  const CameraIntrinsics full = sim::make_default_site().cameras[0].color;
  const CameraIntrinsics recorded = scaled_intrinsics(full, kRecordedScale);
  REQUIRE(recorded.width != full.width);

  site::SiteReplay as_recorded(write_recording_site_inputs("sizes-recorded", 1, CalibrationSizes::Recorded), 0, 4);
  CHECK(as_recorded.cameras()[0].color.intrinsics.width == recorded.width);
  CHECK(as_recorded.cameras()[0].color.intrinsics.fx == recorded.fx);

  site::SiteReplay stated(write_recording_site_inputs("sizes-stated", 1, CalibrationSizes::ScaleStated), 0, 4);
  CHECK(stated.cameras()[0].color.intrinsics.width == recorded.width);
  CHECK(stated.cameras()[0].color.intrinsics.fx == Approx(recorded.fx));
  CHECK(stated.cameras()[0].depth.intrinsics.height == scaled_intrinsics(sim::make_default_site().cameras[0].depth, kRecordedScale).height);

  const std::filesystem::path unstated = write_recording_site_inputs("sizes-unstated", 1, CalibrationSizes::Unstated);
  CHECK_THROWS_WITH(site::SiteReplay(unstated, 0, 4),
                    Contains(sim::color_path(unstated, 0, 0).string()) &&
                        Contains(std::to_string(recorded.width) + "x" + std::to_string(recorded.height)) &&
                        Contains(std::to_string(full.width) + "x" + std::to_string(full.height)) && Contains("recorded_scale"));

  const std::filesystem::path wrong_scale = write_recording_site_inputs("sizes-wrong-scale", 1, CalibrationSizes::ScaleStated);
  nlohmann::json calibration = config::read_json_file(wrong_scale / "calibration.json");
  calibration["recorded_scale"] = 0.5;
  config::write_json_file(wrong_scale / "calibration.json", calibration);
  const CameraIntrinsics at_half = scaled_intrinsics(full, 0.5);
  CHECK_THROWS_WITH(site::SiteReplay(wrong_scale, 0, 4),
                    Contains("expected " + std::to_string(at_half.width) + "x" + std::to_string(at_half.height)) &&
                        Contains("not decoded"));
  calibration["recorded_scale"] = "half";
  config::write_json_file(wrong_scale / "calibration.json", calibration);
  CHECK_THROWS_WITH(site::SiteReplay(wrong_scale, 0, 4), Contains("calibration.json") && Contains("recorded_scale"));
}

TEST_CASE("a bad recording is refused before the site connects, naming the file", "[site_inputs][replay]") {
  CHECK_THROWS_WITH(site::SiteReplay(kOutSiteInputs / "no-such-recording", 0, 4),
                    Contains("no-such-recording") && Contains("does not exist"));

  std::filesystem::path dir = write_recording_site_inputs("bad-format");
  nlohmann::json calibration = config::read_json_file(dir / "calibration.json");
  calibration["format"] = "something-else/2";
  config::write_json_file(dir / "calibration.json", calibration);
  CHECK_THROWS_WITH(site::SiteReplay(dir, 0, 4), Contains("calibration.json") && Contains("something-else/2"));

  dir = write_recording_site_inputs("broken-calibration");
  std::ofstream(dir / "calibration.json") << "{\"format\": \"remotetouch-recording/1\", \"cameras\": [";
  CHECK_THROWS_WITH(site::SiteReplay(dir, 0, 4), Contains("calibration.json") && Contains("not valid JSON"));

  dir = write_recording_site_inputs("too-few-cameras");
  CHECK_THROWS_WITH(site::SiteReplay(dir, 0, 7), Contains("calibration.json") && Contains("has 6 cameras"));

  dir = write_recording_site_inputs("missing-image");
  std::filesystem::remove(sim::depth_path(dir, 4, 2));
  CHECK_THROWS_WITH(site::SiteReplay(dir, 0, 4), Contains(sim::depth_path(dir, 4, 2).string()));
  CHECK_NOTHROW(site::SiteReplay(dir, 2, 4));  // the frames played are all there

  dir = write_recording_site_inputs("unreadable-image");
  std::ofstream(sim::color_path(dir, 2, 0)) << "not a png";
  CHECK_THROWS_WITH(site::SiteReplay(dir, 0, 4), Contains(sim::color_path(dir, 2, 0).string()));

  dir = write_recording_site_inputs("unreadable-later");
  std::ofstream(sim::color_path(dir, 3, 2)) << "not a png";
  site::SiteReplay later(dir, 0, 4);  // only the first frame is read at start
  CHECK_THROWS_WITH(later.read(2), Contains(sim::color_path(dir, 3, 2).string()));

  dir = write_recording_site_inputs("wrong-size");
  write_image(sim::color_path(dir, 1, 0), HostImage(10, 10, PixelFormat::RGBA8));
  CHECK_THROWS_WITH(site::SiteReplay(dir, 0, 4), Contains(sim::color_path(dir, 1, 0).string()) && Contains("10x10"));

  // No tracker recording (as `record` and the vendor's recorder leave a folder): the cameras play,
  // and the tracker gives no hands.
  dir = write_recording_site_inputs("no-tracker");
  std::filesystem::remove(dir / "tracker.jsonl");
  site::SiteReplay no_tracker(dir, 0, 4);
  CHECK_FALSE(no_tracker.has_tracker());
  CHECK_FALSE(no_tracker.tracker()->next_frame());
  CHECK(no_tracker.frame_count() > 0);
  // One that is there but broken is still refused.
  dir = write_recording_site_inputs("broken-tracker");
  std::ofstream(dir / "tracker.jsonl") << "{\"id\": 1}\n";
  CHECK_THROWS_WITH(site::SiteReplay(dir, 0, 4), Contains("tracker.jsonl"));
}

TEST_CASE("site config: replay relative to the config's folder, motor checked", "[site_inputs]") {
  const std::filesystem::path dir = fresh_dir_site_inputs("config");
  std::ofstream(dir / "site.json") << R"({"site": "B", "replay": "recordings/b", "motor": "simulated"})";
  site::SiteRunOptions options;
  site::apply_site_config(dir / "site.json", options);
  CHECK(options.replay == dir / "recordings/b");
  std::ofstream(dir / "live.json") << R"({"site": "A", "site_file": "sites/live.json"})";
  site::apply_site_config(dir / "live.json", options);
  CHECK(options.site_file == dir / "sites/live.json");
  CHECK(options.motor == "simulated");
  std::ofstream(dir / "bad.json") << R"({"motor": "serial"})";
  CHECK_THROWS_WITH(site::apply_site_config(dir / "bad.json", options), Contains("bad.json") && Contains("'motor'"));
}

TEST_CASE("site config: a Janus room and the bitrate's bounds, the pin's file relative to the config", "[site_inputs]") {
  const std::filesystem::path dir = fresh_dir_site_inputs("config-janus");
  std::ofstream(dir / "room.json") << R"({"transport": "webrtc", "janus": "ws://10.0.0.5:8188", "room": 1234,
    "room_secret": "keys/pin", "janus_ca": "/etc/janus/ca.pem", "bitrate_floor_kbps": 200, "bitrate_ceiling_kbps": 1800})";
  site::SiteRunOptions options;
  site::apply_site_config(dir / "room.json", options);
  CHECK(options.transport == "webrtc");
  CHECK(options.call.janus == "ws://10.0.0.5:8188");
  CHECK(options.call.room == 1234);
  CHECK(options.call.room_secret_file == dir / "keys/pin");
  CHECK(options.call.janus_ca_file == "/etc/janus/ca.pem");
  CHECK(options.call.bitrate_floor_kbps == 200);
  CHECK(options.call.bitrate_ceiling_kbps == 1800);
  for (const char* bad : {R"({"room": 0})", R"({"room": -3})", R"({"room": 2.5})", R"({"room": "7"})"}) {
    std::ofstream(dir / "bad-room.json") << bad;
    CHECK_THROWS_WITH(site::apply_site_config(dir / "bad-room.json", options), Contains("bad-room.json") && Contains("'room'"));
  }
  std::ofstream(dir / "bad-floor.json") << R"({"bitrate_floor_kbps": 1e9})";
  CHECK_THROWS_WITH(site::apply_site_config(dir / "bad-floor.json", options), Contains("'bitrate_floor_kbps'"));
  std::ofstream(dir / "bad-janus.json") << R"({"janus": 8188})";
  CHECK_THROWS_WITH(site::apply_site_config(dir / "bad-janus.json", options), Contains("'janus'"));
}

TEST_CASE("the ground truth over the background: premultiplied edges are not darkened twice", "[site]") {
  HostImage truth(2, 1, PixelFormat::RGBA8, 0.0f), background(2, 1, PixelFormat::RGBA8, 0.0f);
  for (uint32_t c = 0; c < 3; ++c) {
    truth.at(0, 0, c) = 0.8f;    // fully covered
    truth.at(1, 0, c) = 0.4f;    // half covered: 0.8 premultiplied by 0.5
    background.at(0, 0, c) = background.at(1, 0, c) = 0.2f;
  }
  truth.at(0, 0, 3) = 1.0f;
  truth.at(1, 0, 3) = 0.5f;
  const HostImage shown = site::truth_over_background(truth, background);
  CHECK(shown.at(0, 0, 0) == Approx(0.8f));
  CHECK(shown.at(1, 0, 0) == Approx(0.4f + 0.2f * 0.5f));
  CHECK(shown.at(1, 0, 3) == Approx(1.0f));
}
