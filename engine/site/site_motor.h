#pragma once
// Which motor a site drives (`remotetouch site --motor simulated|usb|auto`): the Arduino on USB
// when it is there, else the simulated one, saying which and why in the log and metrics.json.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "motor/motor.h"
#include "motor/usb_probe.h"

namespace rt::site {

enum class MotorMode { Simulated, Usb, Auto };

// "simulated", "usb" or "auto"; throws std::invalid_argument naming the choices otherwise.
MotorMode parse_motor_mode(const std::string& text);

struct MotorDecision {
  bool use_usb = false;
  std::string description;  // "usb (bus 1 port 1-2 ...)", "simulated: no Arduino Uno 2341:0043 found", ...
  std::string error;        // non-empty: the site must not start (--motor usb without a board)
};

// The choice from what the USB probe found (usb_probe.h); pure, so it is tested without a board.
MotorDecision decide_motor(MotorMode mode, const std::variant<std::vector<motor::UsbBoard>, std::string>& probe,
                           uint16_t vendor_id = 0x2341, uint16_t product_id = 0x0043);

struct SiteMotor {
  std::unique_ptr<motor::Motor> motor;
  std::string description;  // for the log and metrics.json
};

// Probes USB (unless `mode` is Simulated) and opens the chosen motor. A USB board is opened at
// once: opening resets it (about 1.5 s), which must not land on the first touch. In auto mode a
// board that cannot be opened falls back to the simulated motor with the reason; with --motor
// usb it throws, as does usb without a board. `log` gets the USB driver's status lines. A simulated
// motor is felt `simulated_latency` after each command, as the real one's spin-up.
SiteMotor open_site_motor(MotorMode mode, const std::function<void(const std::string&)>& log,
                          std::chrono::microseconds simulated_latency = {});

}  // namespace rt::site
