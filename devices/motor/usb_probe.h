#pragma once
// Is the motor's board attached? Lists the USB devices with the board's id without opening
// them: no reset of the board (opening one does, usb_motor.h), no permissions needed, so a site
// can choose between the USB and the simulated motor at start and say why.
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace rt::motor {

struct UsbBoard {
  int bus = 0;
  int address = 0;
  std::string port_path;  // "1-2.3": bus, then the hub ports from the root (stable across replugs)
  // "bus 1 port 1-2.3 (address 4)"
  std::string where() const;
};

// "2341:0043"
std::string usb_id_text(uint16_t vendor_id, uint16_t product_id);

// The attached devices with this vendor and product id, in libusb's order; or why the bus could
// not be listed (libusb does not start, no USB here).
std::variant<std::vector<UsbBoard>, std::string> find_usb_boards(uint16_t vendor_id, uint16_t product_id);

}  // namespace rt::motor
