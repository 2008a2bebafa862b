// The libusb motor driver against an Arduino Uno emulated under umockdev (2341:0043, the real
// 16U2 descriptors, the firmware's own parser answering). Runs under umockdev-wrapper; see
// tests/motor.cmake.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "site/site_motor.h"
#include "motor/emulated_uno.h"
#include "motor/usb_motor.h"
#include "motor/usb_probe.h"

using namespace std::chrono_literals;
using rt::motor::EmulatedUno;
using rt::motor::UnoDescriptorOptions;
using rt::motor::UsbMotor;
using rt::motor::UsbMotorOptions;

namespace {

uint64_t steady_now_us() {
  return uint64_t(
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count());
}

// The emulated board and a driver for it; the driver is closed before the board's test bed goes.
struct Bench {
  EmulatedUno uno;
  std::vector<std::string> log;
  std::unique_ptr<UsbMotor> motor;

  explicit Bench(const UnoDescriptorOptions& descriptors = {}) { uno.plug(descriptors); }
  ~Bench() { motor.reset(); }

  UsbMotor& open_driver() {
    UsbMotorOptions options;
    // Short, so that the failure cases stay fast, yet long enough for the emulated board's thread
    // to answer while ctest -j runs CPU-bound Vulkan tests on the same two cores (50 ms was not).
    options.reply_timeout = 400ms;
    options.ready_timeout = 1000ms;
    // The drain stops once input has been quiet this long: a loaded machine can pause the
    // emulated board's thread for a few milliseconds mid-garbage (5 ms was not enough).
    options.drain_quiet = 50ms;
    options.retry_initial = 5ms;
    options.retry_max = 20ms;
    options.log = [this](const std::string& line) { log.push_back(line); };
    motor = std::make_unique<UsbMotor>(options);
    return *motor;
  }

  bool logged(const std::string& needle) const {
    return std::any_of(log.begin(), log.end(), [&](const std::string& line) { return line.find(needle) != line.npos; });
  }
  std::string all_log() const {
    std::string all;
    for (const std::string& line : log) all += line + "\n";
    return all;
  }
};

bool contains(const std::vector<std::string>& events, const std::string& event) {
  return std::find(events.begin(), events.end(), event) != events.end();
}

}  // namespace

TEST_CASE("motor usb: runs under umockdev-wrapper", "[motor][usb]") {
  // Without the preload library the test bed is invisible to libusb and every case below would
  // test the machine's real USB bus instead.
  REQUIRE_NOTHROW(EmulatedUno());
}

TEST_CASE("motor usb: options that make no sense are refused with the reason", "[motor][usb]") {
  UsbMotorOptions options;
  options.reply_timeout = 0ms;
  CHECK_THROWS_WITH(UsbMotor(options), "UsbMotorOptions::reply_timeout must be positive, not 0 ms");
  options = UsbMotorOptions{};
  options.retry_initial = 5s;
  CHECK_THROWS_WITH(UsbMotor(options), "UsbMotorOptions::retry_initial (5000 ms) must not exceed retry_max (2000 ms)");
}

TEST_CASE("motor usb: opening configures the CDC-ACM port and waits for READY", "[motor][usb]") {
  Bench bench;
  UsbMotor& motor = bench.open_driver();
  const auto status = motor.connect();
  INFO(bench.all_log());
  REQUIRE(status.ok());
  CHECK(motor.connected());
  CHECK(motor.firmware() == "remotetouch-motor 1");

  const auto requests = bench.uno.control_requests();
  REQUIRE(requests.size() == 3);
  // SET_LINE_CODING to interface 0: 115200 (0x0001C200, little endian), 1 stop bit, no parity, 8 bits.
  CHECK(requests[0].request_type == 0x21);
  CHECK(requests[0].request == 0x20);
  CHECK(requests[0].value == 0);
  CHECK(requests[0].index == 0);
  CHECK(requests[0].data == std::vector<uint8_t>{0x00, 0xc2, 0x01, 0x00, 0x00, 0x00, 0x08});
  // SET_CONTROL_LINE_STATE: DTR and RTS dropped, then asserted; the edge resets the board.
  CHECK(requests[1].request_type == 0x21);
  CHECK(requests[1].request == 0x22);
  CHECK(requests[1].value == 0x0000);
  CHECK(requests[1].index == 0);
  CHECK(requests[2].request == 0x22);
  CHECK(requests[2].value == 0x0003);
  CHECK(requests[2].data.empty());
  CHECK(bench.uno.resets() == 1);

  const auto events = bench.uno.events();
  CHECK(contains(events, "detach 0"));
  CHECK(contains(events, "claim 0"));
  CHECK(contains(events, "detach 1"));
  CHECK(contains(events, "claim 1"));
  CHECK(bench.uno.received().empty());  // nothing is sent before a command
}

TEST_CASE("motor usb: commands are the exact protocol lines on the bulk OUT endpoint", "[motor][usb]") {
  Bench bench;
  UsbMotor& motor = bench.open_driver();
  const auto pulse = motor.pulse(120ms, 200);
  INFO(bench.all_log());
  REQUIRE(pulse.ok());
  CHECK(bench.uno.received() == "P 120 200\n");
  CHECK(bench.uno.bulk_outs().size() == 1);  // one line, one transfer
  CHECK(bench.uno.motor_strength() == 200);

  REQUIRE(motor.stop().ok());
  CHECK(bench.uno.received() == "P 120 200\nS\n");
  CHECK(bench.uno.motor_strength() == 0);

  std::string version;
  REQUIRE(motor.query_version(version).ok());
  CHECK(version == "remotetouch-motor 1");

  REQUIRE(motor.pulse(1000ms, 255).ok());
  REQUIRE(motor.pulse(1ms, 1).ok());
  CHECK(bench.uno.received() == "P 120 200\nS\nV\nP 1000 255\nP 1 1\n");
}

TEST_CASE("motor usb: values out of bounds are refused before anything is sent", "[motor][usb]") {
  Bench bench;
  UsbMotor& motor = bench.open_driver();
  CHECK(motor.pulse(0ms, 100).error().find("pulse duration 0 ms is out of range 1..1000 ms") == 0);
  CHECK(motor.pulse(1001ms, 100).error().find("pulse duration 1001 ms is out of range") == 0);
  CHECK(motor.pulse(100ms, 0).error().find("pulse strength 0 is out of range 1..255") == 0);
  CHECK(motor.pulse(100ms, 256).error().find("pulse strength 256 is out of range 1..255") == 0);
  CHECK(bench.uno.received().empty());
  CHECK(bench.uno.control_requests().empty());  // not even opened: the check comes first
}

TEST_CASE("motor usb: endpoints come from the descriptors", "[motor][usb]") {
  SECTION("other endpoint numbers") {
    Bench bench(UnoDescriptorOptions{0x81, 0x02, 0x85, true});
    UsbMotor& motor = bench.open_driver();
    const auto status = motor.pulse(30ms, 90);
    INFO(bench.all_log() << status.error());
    REQUIRE(status.ok());
    CHECK(bench.uno.received() == "P 30 90\n");
  }
  SECTION("no CDC data interface") {
    Bench bench(UnoDescriptorOptions{0x82, 0x04, 0x83, false});
    UsbMotor& motor = bench.open_driver();
    const auto status = motor.connect();
    CHECK_FALSE(status.ok());
    CHECK(status.error() ==
          "motor not connected: 2341:0043 on bus 1 address 1: no CDC data interface (class 0x0A) with a bulk IN and "
          "a bulk OUT endpoint: is it an Arduino Uno with its stock USB-serial bridge firmware?");
    CHECK(bench.uno.events().empty());  // rejected from the descriptors alone, nothing claimed
  }
}

TEST_CASE("motor usb: the start-up line proves the firmware", "[motor][usb]") {
  Bench bench;
  SECTION("noise before READY is skipped") {
    bench.uno.set_ready_line(std::string("\x00\xf0junk\n", 7) + "READY remotetouch-motor 1");
    REQUIRE(bench.open_driver().connect().ok());
    CHECK(bench.logged("ignoring '\\x00' before READY (byte 0x00 is not printable ASCII)"));
  }
  SECTION("another sketch") {
    bench.uno.set_ready_line("READY blink 3");
    const auto status = bench.open_driver().connect();
    CHECK(status.error().find("it runs other firmware: it said 'READY blink 3'") != std::string::npos);
  }
  SECTION("another protocol version") {
    bench.uno.set_ready_line("READY remotetouch-motor 2");
    const auto status = bench.open_driver().connect();
    CHECK(status.error().find("its firmware speaks protocol 2 but this driver speaks 1") != std::string::npos);
  }
  SECTION("no firmware at all") {
    bench.uno.set_ready_line("");
    const auto status = bench.open_driver().connect();
    CHECK(status.error().find("no 'READY remotetouch-motor 1' line within 1000 ms of resetting the board") !=
          std::string::npos);
  }
  CHECK(bench.uno.resets() == 1);
}

TEST_CASE("motor usb: garbage and wrong replies are errors, and the next command works", "[motor][usb]") {
  Bench bench;
  UsbMotor& motor = bench.open_driver();
  REQUIRE(motor.connect().ok());

  bench.uno.replace_next_reply("\x01\x02garbage\n");
  auto status = motor.pulse(120ms, 200);
  CHECK(status.error() ==
        "garbage from the motor (2341:0043 on bus 1 address 1) in reply to 'P 120 200': byte 0x01 is not printable "
        "ASCII in '\\x01'");
  CHECK(motor.pulse(120ms, 200).ok());

  bench.uno.replace_next_reply(std::string(200, 'A'));  // no line end at all
  status = motor.stop();
  CHECK(status.error().find("line longer than 63 bytes") != std::string::npos);
  CHECK(motor.stop().ok());  // the rest of the garbage was drained, not taken for this reply

  bench.uno.replace_next_reply("OK P 1 1\n");  // a reply, but to another command
  status = motor.pulse(120ms, 200);
  CHECK(status.error() ==
        "unexpected reply from the motor (2341:0043 on bus 1 address 1) to 'P 120 200': 'OK P 1 1' (expected "
        "'OK P 120 200' or 'ERR <reason>')");

  bench.uno.replace_next_reply("ERR strength 200 out of range 1..255\n");
  status = motor.pulse(120ms, 200);
  CHECK(status.error() == "the motor rejected 'P 120 200': strength 200 out of range 1..255");

  bench.uno.replace_next_reply("READY remotetouch-motor 1\nOK P 120 200\n");
  CHECK(motor.pulse(120ms, 200).ok());
  CHECK(bench.logged("the board restarted ('READY remotetouch-motor 1') while 'P 120 200' waited for its reply"));

  bench.uno.set_silent(true);
  status = motor.pulse(120ms, 200);
  CHECK(status.error() == "no reply from the motor (2341:0043 on bus 1 address 1) to 'P 120 200' within 400 ms");
  bench.uno.set_silent(false);
  CHECK(motor.pulse(120ms, 200).ok());
  CHECK(motor.connected());  // none of this needed a reconnect
  CHECK(bench.uno.resets() == 1);
}

TEST_CASE("motor usb: unplugging is reported and the next command reconnects", "[motor][usb]") {
  Bench bench;
  UsbMotor& motor = bench.open_driver();
  REQUIRE(motor.pulse(100ms, 50).ok());

  std::string failed_step;
  SECTION("between commands") {
    bench.uno.unplug();
    failed_step = "sending 'P 100 60' to bulk OUT endpoint 0x04 failed";
  }
  SECTION("while the driver waits for a reply") {
    bench.uno.unplug_on_next_read();
    failed_step = "reading bulk IN endpoint 0x83 failed";
  }

  const auto lost = motor.pulse(100ms, 60);
  CHECK_FALSE(lost.ok());
  CHECK(lost.error().find("motor 2341:0043 on bus 1 address 1 was unplugged: " + failed_step) == 0);
  CHECK(lost.error().find("LIBUSB_ERROR_NO_DEVICE") != std::string::npos);
  CHECK(lost.error().find("it is reopened on the next command") != std::string::npos);
  CHECK(bench.logged("was unplugged"));
  CHECK_FALSE(motor.connected());

  const auto absent = motor.pulse(100ms, 70);
  CHECK(absent.error() ==
        "motor not connected: no USB device 2341:0043 (Arduino Uno) is attached: is the motor's board plugged in?");
  CHECK(bench.logged("cannot open the motor: no USB device 2341:0043"));

  bench.uno.plug();
  std::this_thread::sleep_for(25ms);  // past the retry backoff (at most 20 ms here)
  const auto back = motor.pulse(100ms, 80);
  INFO(bench.all_log());
  REQUIRE(back.ok());
  CHECK(bench.logged("motor connected: 2341:0043 on bus 1 address 2"));
  CHECK(bench.uno.control_requests().size() == 3);  // configured again from scratch
  CHECK(bench.uno.resets() == 1);
  CHECK(bench.uno.received() == "P 100 80\n");
  CHECK(bench.uno.motor_strength() == 80);
}

TEST_CASE("motor usb: the probe finds the board without opening it; a site's auto motor uses it", "[motor][usb]") {
  EmulatedUno uno;
  auto probe = rt::motor::find_usb_boards(0x2341, 0x0043);
  REQUIRE(std::holds_alternative<std::vector<rt::motor::UsbBoard>>(probe));
  CHECK(std::get<std::vector<rt::motor::UsbBoard>>(probe).empty());
  CHECK_THROWS_WITH(rt::site::open_site_motor(rt::site::MotorMode::Usb, {}),
                    "--motor usb: no Arduino Uno 2341:0043 found on USB; plug in the motor's board or use --motor simulated");
  CHECK(rt::site::open_site_motor(rt::site::MotorMode::Auto, {}).description == "simulated: no Arduino Uno 2341:0043 found");

  uno.plug();
  probe = rt::motor::find_usb_boards(0x2341, 0x0043);
  REQUIRE(std::holds_alternative<std::vector<rt::motor::UsbBoard>>(probe));
  const auto& boards = std::get<std::vector<rt::motor::UsbBoard>>(probe);
  REQUIRE(boards.size() == 1);
  CHECK(boards[0].bus == 1);
  CHECK(boards[0].where().rfind("bus 1 port 1", 0) == 0);
  CHECK(uno.resets() == 0);  // listing does not open (and so does not reset) the board
  CHECK(std::get<std::vector<rt::motor::UsbBoard>>(rt::motor::find_usb_boards(0x2341, 0x0001)).empty());

  std::vector<std::string> log;
  rt::site::SiteMotor site = rt::site::open_site_motor(rt::site::MotorMode::Auto, [&](const std::string& line) { log.push_back(line); });
  INFO(site.description);
  CHECK(site.description.rfind("usb (bus 1 port 1", 0) == 0);
  CHECK(site.description.find("firmware 'remotetouch-motor 1'") != std::string::npos);
  CHECK(uno.resets() == 1);  // opened at start, not on the first touch
  REQUIRE(site.motor->pulse(150ms, 200).ok());
  CHECK(uno.received() == "P 150 200\n");
  site.motor.reset();
}

TEST_CASE("motor usb: closing stops the motor and gives the port back to cdc_acm", "[motor][usb]") {
  Bench bench;
  REQUIRE(bench.open_driver().pulse(500ms, 100).ok());
  CHECK_FALSE(bench.uno.kernel_driver_bound(0));
  CHECK_FALSE(bench.uno.kernel_driver_bound(1));
  bench.motor.reset();
  CHECK(bench.uno.received() == "P 500 100\nS\n");
  CHECK(bench.uno.motor_strength() == 0);
  CHECK(bench.uno.kernel_driver_bound(0));
  CHECK(bench.uno.kernel_driver_bound(1));
  const auto events = bench.uno.events();
  CHECK(contains(events, "release 0"));
  CHECK(contains(events, "attach 0"));
  CHECK(contains(events, "release 1"));
  CHECK(contains(events, "attach 1"));
}

TEST_CASE("motor usb: latency from pulse() to the bulk OUT transfer", "[motor][usb][latency]") {
  Bench bench;
  UsbMotor& motor = bench.open_driver();
  REQUIRE(motor.connect().ok());
  constexpr int kPulses = 200;
  std::vector<uint64_t> called(kPulses), returned(kPulses);
  for (int i = 0; i < kPulses; ++i) {
    called[i] = steady_now_us();
    const auto status = motor.pulse(20ms, 1 + i % 255);
    returned[i] = steady_now_us();
    REQUIRE(status.ok());
  }
  const auto outs = bench.uno.bulk_outs();
  REQUIRE(outs.size() == size_t(kPulses));
  std::vector<uint64_t> to_submit, round_trip;
  for (int i = 0; i < kPulses; ++i) {
    REQUIRE(outs[i].bytes == "P 20 " + std::to_string(1 + i % 255) + "\n");
    REQUIRE(outs[i].submitted_us >= called[i]);
    REQUIRE(outs[i].submitted_us <= returned[i]);
    to_submit.push_back(outs[i].submitted_us - called[i]);
    round_trip.push_back(returned[i] - called[i]);
  }
  const auto percentile = [](std::vector<uint64_t> values, double p) {
    std::sort(values.begin(), values.end());
    return values[size_t(p * double(values.size() - 1))];
  };
  std::cout << "motor latency over " << kPulses << " pulses, emulated Uno under umockdev:\n"
            << "  pulse() called -> bulk OUT URB submitted to the device: median " << percentile(to_submit, 0.5)
            << " us, p90 " << percentile(to_submit, 0.9) << " us\n"
            << "  pulse() called -> returned with the OK reply read:     median " << percentile(round_trip, 0.5)
            << " us, p90 " << percentile(round_trip, 0.9) << " us\n";
}
