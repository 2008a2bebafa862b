#include "motor/usb_probe.h"

#include <array>
#include <cstdio>
#include <exception>

#include "motor/usb_handles.h"

namespace rt::motor {

std::string UsbBoard::where() const {
  return "bus " + std::to_string(bus) + " port " + port_path + " (address " + std::to_string(address) + ")";
}

std::string usb_id_text(uint16_t vendor_id, uint16_t product_id) {
  char text[16];
  std::snprintf(text, sizeof text, "%04x:%04x", unsigned(vendor_id), unsigned(product_id));
  return text;
}

std::variant<std::vector<UsbBoard>, std::string> find_usb_boards(uint16_t vendor_id, uint16_t product_id) {
  usb::Context context;
  try {
    context = usb::make_context();
  } catch (const std::exception& error) {
    return std::string(error.what());
  }
  usb::DeviceList list;
  if (const int result = list.fill(context.get()); result < 0) return "cannot list USB devices: " + usb::error_text(result);
  std::vector<UsbBoard> boards;
  for (libusb_device* device : list.devices()) {
    libusb_device_descriptor descriptor;
    if (libusb_get_device_descriptor(device, &descriptor) != 0 || descriptor.idVendor != vendor_id ||
        descriptor.idProduct != product_id)
      continue;
    UsbBoard board;
    board.bus = libusb_get_bus_number(device);
    board.address = libusb_get_device_address(device);
    board.port_path = std::to_string(board.bus);
    std::array<uint8_t, 8> ports{};  // USB 3 allows 7 tiers of hubs
    const int depth = libusb_get_port_numbers(device, ports.data(), int(ports.size()));
    for (int i = 0; i < depth; ++i) board.port_path += (i == 0 ? "-" : ".") + std::to_string(ports[size_t(i)]);
    boards.push_back(std::move(board));
  }
  return boards;
}

}  // namespace rt::motor
