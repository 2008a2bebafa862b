#pragma once
// The parts of USB CDC-ACM (USB CDC 1.2, PSTN subclass 1.2) the motor needs: where the serial
// port's endpoints are, and the two class requests that configure it.
#include <libusb.h>

#include <array>
#include <cstdint>
#include <string>
#include <variant>

namespace rt::motor::cdc {

// Endpoints differ between bridge firmwares (16U2 revisions, clones), so they come from the
// descriptors, never from constants.
struct Layout {
  uint8_t control_interface = 0;      // class 0x02 (CDC), subclass 0x02 (ACM)
  uint8_t notification_endpoint = 0;  // its interrupt IN endpoint (serial state)
  uint8_t data_interface = 0;         // class 0x0A (CDC data)
  uint8_t bulk_in = 0;
  uint8_t bulk_out = 0;
  uint16_t bulk_in_max_packet = 0;
};

// The layout, or what is missing from the configuration.
std::variant<Layout, std::string> find_layout(const libusb_config_descriptor& config);

// Class request to the control interface: host to device, class, recipient interface.
constexpr uint8_t kRequestTypeClassInterfaceOut =
    unsigned(LIBUSB_ENDPOINT_OUT) | unsigned(LIBUSB_REQUEST_TYPE_CLASS) | unsigned(LIBUSB_RECIPIENT_INTERFACE);
static_assert(kRequestTypeClassInterfaceOut == 0x21);
constexpr uint8_t kSetLineCoding = 0x20;
constexpr uint8_t kSetControlLineState = 0x22;
constexpr uint16_t kControlLineDtr = 0x01;
constexpr uint16_t kControlLineRts = 0x02;

// The 7-byte line coding: dwDTERate (little endian), bCharFormat (0: 1 stop bit),
// bParityType (0: none), bDataBits.
std::array<uint8_t, 7> line_coding_8n1(uint32_t baud);

}  // namespace rt::motor::cdc
