// Leap v6 JSON frames: written one per line and read back exactly; a real device's frame (with
// fields we do not use) parses; fields that some service versions leave out are derived from the
// digits, close to what the service would have sent; a malformed frame is refused with an error
// naming the field and never crashes the reader; a recorded tracker.jsonl replays the simulated
// frames bit for bit, and a bad one (or one with an endless line) is refused when checked.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "config/assets.h"
#include "config/json.h"
#include "sim/leap_json.h"
#include "sim/scene.h"
#include "sim/tracker_replay.h"
#include "sim/tracker_sim.h"
#include "sim/tracker_space.h"
#include "support/output_dir.h"

using namespace rt;
using namespace rt::sim;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kScenesSimLeapJson = rt::config::assets_dir() / "scenes";
const std::filesystem::path kOutSimLeapJson = rt::test::output_dir("test_sim_leap_json");

std::vector<TrackerFrame> simulate_sim_leap_json(const std::string& scene_name, Site site) {
  SimulatedHandTracker tracker = make_simulated_tracker(load_scene(kScenesSimLeapJson / (scene_name + ".json")), site);
  std::vector<TrackerFrame> frames;
  while (std::optional<TrackerFrame> frame = tracker.next_frame()) frames.push_back(*frame);
  return frames;
}

TrackerFrame frame_with_a_hand() {
  for (const TrackerFrame& frame : simulate_sim_leap_json("clap", Site::A))
    if (!frame.hands.empty()) return frame;
  FAIL("the clap scene never shows a hand to the tracker");
  return {};
}

// A frame as the Leap service sends it (shortened): extra fields the project does not read.
const char* const kDeviceFrame = R"({"currentFrameRate":110.2,"devices":[],"id":84262,"timestamp":3360417211,
 "r":[[1,0,0],[0,1,0],[0,0,1]],"s":1.0,"t":[0,0,0],"interactionBox":{"center":[0,200,0],"size":[235,235,147]},
 "hands":[{"id":57,"type":"right","confidence":0.92,"palmPosition":[31.2,182.4,-12.5],"palmNormal":[0.0,-1.0,0.0],
   "direction":[0.0,0.0,-1.0],"wrist":[28.0,170.1,48.0],"elbow":[20.0,120.0,290.0],"palmWidth":84.9,
   "grabStrength":0,"pinchStrength":0,"palmVelocity":[1,2,3],"sphereRadius":80,"timeVisible":1.2,
   "armBasis":[[1,0,0],[0,1,0],[0,0,1]],"armWidth":60}],
 "pointables":[
  {"id":570,"handId":57,"type":0,"carpPosition":[10,180,30],"mcpPosition":[10,180,30],"pipPosition":[0,180,0],"dipPosition":[-10,180,-20],"btipPosition":[-15,180,-40],"tipPosition":[-15,180,-40],"bases":[],"extended":true,"length":50,"width":20},
  {"id":571,"handId":57,"type":1,"carpPosition":[20,180,40],"mcpPosition":[20,182,-20],"pipPosition":[20,182,-60],"dipPosition":[20,182,-85],"btipPosition":[20,182,-105],"tipPosition":[20,182,-105],"extended":true},
  {"id":572,"handId":57,"type":2,"carpPosition":[30,180,40],"mcpPosition":[32,182,-22],"pipPosition":[32,182,-66],"dipPosition":[32,182,-94],"btipPosition":[32,182,-114],"tipPosition":[32,182,-114]},
  {"id":573,"handId":57,"type":3,"carpPosition":[40,180,40],"mcpPosition":[48,182,-18],"pipPosition":[48,182,-60],"dipPosition":[48,182,-86],"btipPosition":[48,182,-106],"tipPosition":[48,182,-106]},
  {"id":574,"handId":57,"type":4,"carpPosition":[50,180,40],"mcpPosition":[62,182,-8],"pipPosition":[62,182,-40],"dipPosition":[62,182,-59],"btipPosition":[62,182,-77],"tipPosition":[62,182,-77]}],
 "gestures":[]})";

void require_rejected(const nlohmann::json& json, const std::string& part1, const std::string& part2 = "") {
  try {
    frame_from_leap_json(json);
    FAIL("accepted a malformed frame: " << json.dump());
  } catch (const config::JsonError& error) {
    CHECK_THAT(error.what(), Contains(part1) && Contains(part2));
  }
}

}  // namespace

TEST_CASE("frames written as Leap v6 JSON read back exactly", "[sim][leap_json]") {
  int with_hands = 0;
  for (const TrackerFrame& frame : simulate_sim_leap_json("noisy-clap", Site::B)) {
    const std::string line = leap_json_line(frame);
    REQUIRE(line.find('\n') == std::string::npos);  // one frame per line
    CHECK(parse_leap_json_line(line) == frame);
    with_hands += !frame.hands.empty();
  }
  CHECK(with_hands > 20);
  // The fields the protocol names, with its units and names.
  const nlohmann::json json = leap_json_from_frame(frame_with_a_hand());
  for (const char* field : {"id", "timestamp", "hands", "pointables"}) CHECK(json.contains(field));
  const nlohmann::json& hand = json["hands"][0];
  for (const char* field : {"id", "type", "confidence", "palmPosition", "palmNormal", "direction", "wrist", "elbow", "palmWidth"})
    CHECK(hand.contains(field));
  CHECK(hand["type"] == "right");
  CHECK(hand["palmWidth"].get<double>() > 50.0);  // millimetres
  REQUIRE(json["pointables"].size() == 5);
  for (int type = 0; type < 5; ++type) {
    const nlohmann::json& pointable = json["pointables"][type];
    CHECK(pointable["type"] == type);
    CHECK(pointable["handId"] == hand["id"]);
    for (const char* field : {"carpPosition", "mcpPosition", "pipPosition", "dipPosition", "btipPosition", "tipPosition"})
      CHECK(pointable.contains(field));
  }
  CHECK(json["pointables"][0]["carpPosition"] == json["pointables"][0]["mcpPosition"]);  // thumb
}

TEST_CASE("a device's frame, with fields we do not read, parses", "[sim][leap_json]") {
  const TrackerFrame frame = parse_leap_json_line(kDeviceFrame);
  CHECK(frame.id == 84262);
  CHECK(frame.timestamp_us == 3360417211u);
  REQUIRE(frame.hands.size() == 1);
  const TrackerHand& hand = frame.hands[0];
  CHECK(hand.id == 57);
  CHECK_FALSE(hand.is_left);
  CHECK(hand.confidence == Approx(0.92));
  CHECK(hand.palm_position == Eigen::Vector3d(31.2, 182.4, -12.5));
  CHECK(hand.digits[2].tip == Eigen::Vector3d(32, 182, -114));
  CHECK(hand.digits[4].mcp == Eigen::Vector3d(62, 182, -8));
  REQUIRE(hand.elbow.has_value());
  CHECK(*hand.elbow == Eigen::Vector3d(20.0, 120.0, 290.0));
  REQUIRE(hand.arm_width.has_value());
  CHECK(*hand.arm_width == 60.0);
  // And a frame without hands.
  CHECK(parse_leap_json_line(R"({"id": 3, "timestamp": 60000, "hands": [], "pointables": []})").hands.empty());
}

TEST_CASE("a frame without an elbow or an arm width has no forearm: nothing is invented", "[sim][leap_json]") {
  nlohmann::json json = nlohmann::json::parse(kDeviceFrame);
  json["hands"][0].erase("elbow");
  json["hands"][0].erase("armWidth");
  const TrackerFrame frame = frame_from_leap_json(json);
  REQUIRE(frame.hands.size() == 1);
  CHECK_FALSE(frame.hands[0].elbow.has_value());
  CHECK_FALSE(frame.hands[0].arm_width.has_value());
  const nlohmann::json written = leap_json_from_frame(frame);
  CHECK_FALSE(written["hands"][0].contains("elbow"));
  CHECK_FALSE(written["hands"][0].contains("armWidth"));
  CHECK(frame_from_leap_json(written) == frame);
  // In the site frame: NaN elbow and arm width, the palm width in metres.
  const HandSkeleton skeleton = skeleton_from_tracker_hand(frame.hands[0], frame.timestamp_us, TrackerPlacement{});
  CHECK_FALSE(skeleton.has_elbow());
  CHECK(std::isnan(skeleton.arm_width_m));
  CHECK(skeleton.palm_width_m == Approx(0.0849));
  const HandSkeleton with_arm =
      skeleton_from_tracker_hand(parse_leap_json_line(kDeviceFrame).hands[0], frame.timestamp_us, TrackerPlacement{});
  CHECK(with_arm.has_elbow());
  CHECK(with_arm.arm_width_m == Approx(0.060));
}

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / 3.14159265358979;
}

TEST_CASE("fields other service versions leave out are derived from the digits", "[sim][leap_json]") {
  // Every frame with hands of the clap, both sites (right and left hands, many poses), each hand
  // field left out in turn and all at once: derived within a centimetre or two and a few degrees
  // of what the tracker sent (millimetres, the hand about 180 mm long).
  size_t hands_checked = 0;
  for (const Site site : {Site::A, Site::B})
    for (const TrackerFrame& frame : simulate_sim_leap_json("clap", site)) {
      if (frame.hands.empty()) continue;
      const nlohmann::json sent = leap_json_from_frame(frame);
      auto without = [&](std::initializer_list<const char*> fields) {
        nlohmann::json json = sent;
        for (auto& hand : json["hands"])
          for (const char* field : fields) hand.erase(field);
        return frame_from_leap_json(json);
      };
      const TrackerFrame derived = without({"wrist", "direction", "palmPosition", "palmNormal", "confidence", "palmWidth"});
      const TrackerFrame no_wrist = without({"wrist"}), no_direction = without({"direction"});
      const TrackerFrame no_palm = without({"palmPosition"}), no_normal = without({"palmNormal"});
      REQUIRE(derived.hands.size() == frame.hands.size());
      for (size_t h = 0; h < frame.hands.size(); ++h) {
        const TrackerHand& truth = frame.hands[h];
        INFO("site " << (site == Site::A ? "A" : "B") << " frame " << frame.id << (truth.is_left ? " left" : " right"));
        CHECK((no_wrist.hands[h].wrist - truth.wrist).norm() < 15.0);
        CHECK(angle_deg(no_direction.hands[h].direction, truth.direction) < 6.0);
        CHECK((no_palm.hands[h].palm_position - truth.palm_position).norm() < 12.0);
        CHECK(angle_deg(no_normal.hands[h].palm_normal, truth.palm_normal) < 10.0);  // and out of the palm, not into it
        const TrackerHand& all = derived.hands[h];
        CHECK((all.wrist - truth.wrist).norm() < 15.0);
        CHECK(angle_deg(all.direction, truth.direction) < 10.0);
        CHECK(angle_deg(all.palm_normal, truth.palm_normal) < 12.0);
        CHECK((all.palm_position - truth.palm_position).norm() < 15.0);
        CHECK(all.confidence == 1.0);
        CHECK_FALSE(all.palm_width.has_value());
        CHECK(all.digits == truth.digits);  // the digits are what was sent
        // Nothing else changes, and the site frame's skeleton leaves the palm's width unknown.
        CHECK(no_wrist.hands[h].direction == truth.direction);
        CHECK(std::isnan(skeleton_from_tracker_hand(all, frame.timestamp_us, TrackerPlacement{}).palm_width_m));
        ++hands_checked;
      }
    }
  CHECK(hands_checked > 40);
}

TEST_CASE("a digit's missing carp or tip is derived, and a hand that cannot be placed is refused", "[sim][leap_json]") {
  const TrackerFrame frame = frame_with_a_hand();
  const TrackerHand& truth = frame.hands[0];
  const nlohmann::json sent = leap_json_from_frame(frame);
  nlohmann::json json = sent;
  for (auto& pointable : json["pointables"]) pointable.erase("carpPosition");
  json["pointables"][1].erase("btipPosition");
  json["pointables"][2].erase("tipPosition");
  const TrackerHand hand = frame_from_leap_json(json).hands[0];
  CHECK(hand.digits[0].carp == truth.digits[0].mcp);  // the thumb's metacarpal has zero length
  for (int d = 1; d < kDigitCount; ++d) CHECK(hand.digits[size_t(d)].carp == truth.wrist);
  CHECK(hand.digits[1].btip == truth.digits[1].tip);
  CHECK(hand.digits[2].tip == truth.digits[2].btip);
  CHECK(hand.wrist == truth.wrist);

  const std::string hand_id = std::to_string(truth.id);
  nlohmann::json unplaced = sent;
  unplaced["hands"][0].erase("wrist");
  unplaced["pointables"][3].erase("carpPosition");
  require_rejected(unplaced, "hand " + hand_id, "no 'wrist' and no 'carpPosition' for digit 3");
  nlohmann::json no_end = sent;
  no_end["pointables"][4].erase("tipPosition");
  no_end["pointables"][4].erase("btipPosition");
  require_rejected(no_end, "pointables[4]", "neither 'tipPosition' nor 'btipPosition'");
  nlohmann::json null_wrist = sent;  // null is the same as left out
  null_wrist["hands"][0]["wrist"] = nullptr;
  CHECK((frame_from_leap_json(null_wrist).hands[0].wrist - truth.wrist).norm() < 15.0);
  nlohmann::json flat = sent;  // no normal, and the knuckles along the direction: no palm plane
  flat["hands"][0].erase("palmNormal");
  flat["pointables"][4]["mcpPosition"] = flat["pointables"][1]["mcpPosition"];
  require_rejected(flat, "hand " + hand_id, "no 'palmNormal'");
  nlohmann::json huge = sent;  // finite carps whose mean overflows: the wrist cannot be placed
  huge["hands"][0].erase("wrist");
  for (auto& pointable : huge["pointables"]) pointable["carpPosition"] = {1e308, 1e308, 1e308};
  require_rejected(huge, "hand " + hand_id, "'wrist' comes out infinite or NaN");
}

TEST_CASE("malformed frames are refused, naming the field", "[sim][leap_json]") {
  const nlohmann::json good = leap_json_from_frame(frame_with_a_hand());
  const std::string hand_id = std::to_string(good["hands"][0]["id"].get<int>());
  auto changed = [&](auto&& change) {
    nlohmann::json json = good;
    change(json);
    return json;
  };
  CHECK_THROWS_WITH(parse_leap_json_line("{\"id\": 1, \"timestamp\""), Contains("not valid JSON"));
  CHECK_THROWS_WITH(parse_leap_json_line(R"({"id": 1, "timestamp": 1E999, "hands": [], "pointables": []})"),
                    Contains("not valid JSON"));
  require_rejected(nlohmann::json::array(), "must be a JSON object");
  require_rejected(changed([](auto& j) { j.erase("hands"); }), "missing field 'hands'");
  require_rejected(changed([](auto& j) { j.erase("id"); }), "missing field 'id'");
  require_rejected(changed([](auto& j) { j["timestamp"] = -5; }), "'timestamp' must not be negative");
  require_rejected(changed([](auto& j) { j["timestamp"] = "now"; }), "'timestamp'");
  require_rejected(changed([](auto& j) { j["hands"] = nlohmann::json::array({nlohmann::json{{"id", 1}}}); }), "hand 1",
                   "missing field 'type'");
  require_rejected(changed([](auto& j) { j["hands"][0]["type"] = "middle"; }), "hand " + hand_id,
                   "'type' must be \"left\" or \"right\"");
  require_rejected(changed([](auto& j) { j["hands"][0]["palmPosition"] = {1.0, 2.0}; }), "hand " + hand_id,
                   "'palmPosition'");
  require_rejected(changed([](auto& j) { j["hands"][0]["wrist"] = {1.0, "x", 2.0}; }), "'wrist'");
  require_rejected(changed([](auto& j) { j["hands"][0]["palmNormal"] = {0.0, 0.0, 0.0}; }), "'palmNormal' must be a unit vector");
  require_rejected(changed([](auto& j) { j["hands"][0]["confidence"] = 1.5; }), "'confidence'");
  require_rejected(changed([](auto& j) { j["hands"][0]["palmWidth"] = -3; }), "'palmWidth'");
  require_rejected(changed([](auto& j) { j["hands"][0]["elbow"] = {1.0, 2.0}; }), "hand " + hand_id, "'elbow'");
  require_rejected(changed([](auto& j) { j["hands"][0]["armWidth"] = 0; }), "hand " + hand_id, "'armWidth'");
  require_rejected(changed([](auto& j) { j["hands"][0]["armWidth"] = "wide"; }), "'armWidth'");
  require_rejected(changed([](auto& j) { j["hands"].push_back(j["hands"][0]); }), "two hands have id " + hand_id);
  require_rejected(changed([](auto& j) { j["pointables"][2]["type"] = 7; }), "pointables[2]", "'type' must be in [0, 4]");
  require_rejected(changed([](auto& j) { j["pointables"][3]["type"] = 1; }), "two pointables of type 1");
  require_rejected(changed([](auto& j) { j["pointables"][1]["handId"] = 999; }), "pointables[1]",
                   "'handId' names hand 999");
  require_rejected(changed([](auto& j) { j["pointables"].erase(4); }), "hand " + hand_id, "no pointable of type 4");
  require_rejected(changed([](auto& j) { j["pointables"][0].erase("dipPosition"); }), "pointables[0]",
                   "missing field 'dipPosition'");
  require_rejected(changed([](auto& j) { j["pointables"] = "none"; }), "'pointables' must be an array");
}

TEST_CASE("no mangled line crashes the parser: it parses or gives a JsonError", "[sim][leap_json]") {
  const std::string line = leap_json_line(frame_with_a_hand());
  std::mt19937 random(1234);
  const std::string alphabet = "{}[]\",:-0123456789.eE tnulfas";
  int rejected = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string mangled = line;
    const int edits = 1 + int(random() % 3);
    for (int e = 0; e < edits; ++e) {
      const size_t at = random() % mangled.size();
      switch (random() % 3) {
        case 0: mangled[at] = alphabet[random() % alphabet.size()]; break;
        case 1: mangled.erase(at, 1 + random() % 8); break;
        default: mangled.resize(at); break;
      }
      if (mangled.empty()) mangled.push_back('{');  // not `= "{"`: GCC 12 -O3 misreports -Wrestrict
    }
    try {
      const TrackerFrame frame = parse_leap_json_line(mangled);
      for (const TrackerHand& hand : frame.hands) REQUIRE(hand.palm_position.allFinite());
    } catch (const config::JsonError&) {
      ++rejected;
    }
  }
  CHECK(rejected > 1000);
}

TEST_CASE("replaying a recorded tracker.jsonl gives the simulated frames exactly", "[sim][leap_json]") {
  const std::filesystem::path path = kOutSimLeapJson / "noisy-clap-A" / "tracker.jsonl";
  const Scene scene = load_scene(kScenesSimLeapJson / "noisy-clap.json");
  SimulatedHandTracker recorded = make_simulated_tracker(scene, Site::A);
  const uint64_t written = record_tracker_jsonl(recorded, path);
  CHECK(written == tracker_frame_count(scene));

  SimulatedHandTracker simulated = make_simulated_tracker(scene, Site::A);
  ReplayHandTracker replay(path);
  HandTracker& source = replay;  // used through the interface, as the site pipeline will
  uint64_t replayed = 0, with_hands = 0;
  while (const std::optional<TrackerFrame> expected = simulated.next_frame()) {
    const std::optional<TrackerFrame> got = source.next_frame();
    REQUIRE(got);
    REQUIRE(*got == *expected);
    with_hands += !got->hands.empty();
    ++replayed;
  }
  CHECK_FALSE(source.next_frame());
  CHECK(replayed == written);
  CHECK(with_hands > 20);
}

TEST_CASE("a bad recording names the file and the line", "[sim][leap_json]") {
  std::filesystem::create_directories(kOutSimLeapJson);
  CHECK_THROWS_WITH(ReplayHandTracker(kOutSimLeapJson / "no-such-tracker.jsonl"), Contains("no-such-tracker.jsonl"));

  const std::string good = leap_json_line(frame_with_a_hand());
  const std::filesystem::path broken = kOutSimLeapJson / "broken-tracker.jsonl";
  std::ofstream(broken) << good << "\n\n" << R"({"id": 2, "timestamp": 99999999, "hands": [{"id": 4}], "pointables": []})"
                        << "\n";
  ReplayHandTracker replay(broken);
  CHECK(replay.next_frame());
  CHECK_THROWS_WITH(replay.next_frame(), Contains("broken-tracker.jsonl' line 3") && Contains("missing field 'type'"));

  const std::filesystem::path backwards = kOutSimLeapJson / "backwards-tracker.jsonl";
  std::ofstream(backwards) << R"({"id": 1, "timestamp": 40000, "hands": [], "pointables": []})" << "\n"
                           << R"({"id": 2, "timestamp": 20000, "hands": [], "pointables": []})" << "\n";
  ReplayHandTracker reversed(backwards);
  CHECK(reversed.next_frame());
  CHECK_THROWS_WITH(reversed.next_frame(), Contains("line 2") && Contains("goes back in time"));

  // Checked whole before a site uses it: the bad line is found at once.
  CHECK_THROWS_WITH(check_tracker_recording(broken), Contains("line 3"));
  CHECK_THROWS_WITH(check_tracker_recording(backwards), Contains("line 2"));

  // A line without end (a file of 3 MB and no newline) is refused at the bound, not buffered.
  const std::filesystem::path endless = kOutSimLeapJson / "endless-tracker.jsonl";
  {
    std::ofstream out(endless);
    out << good << "\n";
    const std::string chunk(64 * 1024, ' ');
    for (int i = 0; i < 48; ++i) out << chunk;
  }
  ReplayHandTracker long_line(endless);
  CHECK(long_line.next_frame());
  CHECK_THROWS_WITH(long_line.next_frame(), Contains("line 2") && Contains("longer than 1048576 bytes"));
  const std::filesystem::path two = kOutSimLeapJson / "two-frames-tracker.jsonl";
  std::ofstream(two) << good << "\n\n" << good << "\n";
  CHECK(check_tracker_recording(two) == 2);
}
