// A stand-in for the Leap service, for the site's live-tracker test: serves the scene's simulated
// tracker frames (as the service would send them, in the tracker's own millimetres) over the Leap
// WebSocket protocol on loopback, at 50 Hz of wall-clock time from each client's connection,
// holding the last frame after the scene's end.
//   fake_leap_service SCENE_FILE SITE(A|B) SECONDS
// Prints "listening on PORT", serves for SECONDS, then exits.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>

#include "sim/leap_json.h"
#include "sim/scene.h"
#include "sim/tracker_sim.h"
#include "support/fake_leap_service.h"

using namespace rt;

int main(int argc, char** argv) {
  if (argc != 4 || (std::string(argv[2]) != "A" && std::string(argv[2]) != "B")) {
    std::cerr << "usage: fake_leap_service SCENE_FILE A|B SECONDS\n";
    return 2;
  }
  try {
    const sim::Scene scene = sim::load_scene(argv[1]);
    const Site site = std::string(argv[2]) == "B" ? Site::B : Site::A;
    const double seconds = std::stod(argv[3]);
    std::vector<std::string> lines;
    sim::SimulatedHandTracker tracker = sim::make_simulated_tracker(scene, site);
    while (auto frame = tracker.next_frame()) lines.push_back(sim::leap_json_line(*frame));
    if (lines.empty()) throw std::runtime_error("the scene gives no tracker frames");
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    test::FakeLeapService service(0, [&](test::LeapSocket& ws) {
      test::greet(ws);
      auto next = std::chrono::steady_clock::now();
      for (size_t i = 0; std::chrono::steady_clock::now() < end; ++i) {
        test::send_text(ws, lines[std::min(i, lines.size() - 1)]);
        next += std::chrono::microseconds(sim::kTrackerPeriodUs);
        std::this_thread::sleep_until(next);
      }
    });
    std::cout << "listening on " << service.port() << std::endl;
    std::this_thread::sleep_until(end);
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "fake_leap_service: " << error.what() << "\n";
    return 1;
  }
}
