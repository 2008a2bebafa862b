#include "site/site_motor.h"

#include <stdexcept>

#include "motor/simulated_motor.h"
#include "motor/usb_motor.h"
#include "time/monotonic_clock.h"

namespace rt::site {

MotorMode parse_motor_mode(const std::string& text) {
  if (text == "simulated") return MotorMode::Simulated;
  if (text == "usb") return MotorMode::Usb;
  if (text == "auto") return MotorMode::Auto;
  throw std::invalid_argument("motor '" + text + "': must be simulated, usb or auto");
}

MotorDecision decide_motor(MotorMode mode, const std::variant<std::vector<motor::UsbBoard>, std::string>& probe,
                           uint16_t vendor_id, uint16_t product_id) {
  MotorDecision decision;
  if (mode == MotorMode::Simulated) {
    decision.description = "simulated (--motor simulated)";
    return decision;
  }
  const std::string board = "Arduino Uno " + motor::usb_id_text(vendor_id, product_id);
  std::string missing;
  if (const auto* why = std::get_if<std::string>(&probe)) {
    missing = "no " + board + " found (" + *why + ")";
  } else {
    const auto& boards = std::get<std::vector<motor::UsbBoard>>(probe);
    if (boards.empty()) {
      missing = "no " + board + " found";
    } else {
      decision.use_usb = true;
      // UsbMotor opens the first one libusb lists; say so when there is a choice.
      decision.description = "usb (" + boards.front().where() + ", " + motor::usb_id_text(vendor_id, product_id) + ")";
      if (boards.size() > 1)
        decision.description += "; " + std::to_string(boards.size()) + " such boards attached, the first is used";
      return decision;
    }
  }
  if (mode == MotorMode::Usb)
    decision.error = "--motor usb: " + missing + " on USB; plug in the motor's board or use --motor simulated";
  decision.description = "simulated: " + missing;
  return decision;
}

SiteMotor open_site_motor(MotorMode mode, const std::function<void(const std::string&)>& log,
                          std::chrono::microseconds simulated_latency) {
  const motor::UsbMotorOptions defaults;
  const MotorDecision decision =
      mode == MotorMode::Simulated
          ? decide_motor(mode, std::vector<motor::UsbBoard>{})
          : decide_motor(mode, motor::find_usb_boards(defaults.vendor_id, defaults.product_id), defaults.vendor_id,
                         defaults.product_id);
  if (!decision.error.empty()) throw std::runtime_error(decision.error);
  SiteMotor site;
  if (decision.use_usb) {
    motor::UsbMotorOptions options;
    options.log = log;
    auto usb = std::make_unique<motor::UsbMotor>(options);
    if (const motor::MotorStatus status = usb->connect(); status) {
      site.description = decision.description + ", firmware '" + usb->firmware() + "'";
      site.motor = std::move(usb);
      return site;
    } else if (mode == MotorMode::Usb) {
      throw std::runtime_error("--motor usb: the board is there but cannot be opened: " + status.error());
    } else {
      site.description = "simulated: the " + decision.description + " cannot be opened: " + status.error();
    }
  } else {
    site.description = decision.description;
  }
  site.motor = std::make_unique<motor::SimulatedMotor>(monotonic_now_us, simulated_latency);
  return site;
}

}  // namespace rt::site
