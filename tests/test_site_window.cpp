// A site's window, the parts that need no display: which display a run takes, the present mode,
// the keys, and the site config's fields. The window itself is tested under Xvfb
// (tests/cli/session_window.sh).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "display/glfw_window.h"
#include "display/window_presenter.h"
#include "site/site_options.h"

using namespace rt;
using Catch::Matchers::Contains;

TEST_CASE("display mode: auto is a window only where a display is present", "[site_window]") {
  CHECK(site::parse_display_mode("auto", true) == site::DisplayMode::Window);
  CHECK(site::parse_display_mode("auto", false) == site::DisplayMode::Headless);
  CHECK(site::parse_display_mode("window", false) == site::DisplayMode::Window);
  CHECK(site::parse_display_mode("both", false) == site::DisplayMode::Both);
  CHECK(site::parse_display_mode("headless", true) == site::DisplayMode::Headless);
  CHECK_THROWS_WITH(site::parse_display_mode("screen", true), Contains("'screen'") && Contains("window, headless, both or auto"));
}

TEST_CASE("present mode and keys", "[site_window]") {
  CHECK(display::parse_present_mode("fifo") == display::PresentMode::Fifo);
  CHECK(display::parse_present_mode("mailbox") == display::PresentMode::Mailbox);
  CHECK_THROWS_WITH(display::parse_present_mode("immediate"), Contains("fifo or mailbox"));
  CHECK(display::view_index(display::WindowCommand::View1) == 0);
  CHECK(display::view_index(display::WindowCommand::View8) == 7);
  CHECK(display::view_index(display::WindowCommand::Quit) == -1);
  CHECK(display::view_index(display::WindowCommand::Screenshot) == -1);
}

TEST_CASE("site config: display, monitor and present mode, checked", "[site_window]") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "remotetouch-test-site-window";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "site.json") << R"({"display": "both", "monitor": 1, "present_mode": "mailbox"})";
  site::SiteRunOptions options;
  site::apply_site_config(dir / "site.json", options);
  CHECK(options.display == "both");
  CHECK(options.monitor == 1);
  CHECK(options.present_mode == "mailbox");
  std::ofstream(dir / "bad_display.json") << R"({"display": "tv"})";
  auto apply = [](const std::filesystem::path& file) {
    site::SiteRunOptions fresh;
    site::apply_site_config(file, fresh);
  };
  CHECK_THROWS_WITH(apply(dir / "bad_display.json"), Contains("bad_display.json") && Contains("'display'"));
  std::ofstream(dir / "bad_mode.json") << R"({"present_mode": "immediate"})";
  CHECK_THROWS_WITH(apply(dir / "bad_mode.json"), Contains("'present_mode'"));
  std::ofstream(dir / "bad_monitor.json") << R"({"monitor": 1e9})";
  CHECK_THROWS_WITH(apply(dir / "bad_monitor.json"), Contains("'monitor'"));
}

TEST_CASE("no display: a window is refused saying what to do", "[site_window]") {
  if (site::display_present()) {
    WARN("a display is present here: nothing to refuse");
    return;
  }
  CHECK_THROWS_WITH(display::GlfwWindow::surface_instance_extensions(), Contains("--display headless"));
}
