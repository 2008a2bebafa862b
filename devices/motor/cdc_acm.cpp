#include "motor/cdc_acm.h"

#include <optional>

namespace rt::motor::cdc {
namespace {

constexpr uint8_t kClassCommunications = 0x02;
constexpr uint8_t kSubclassAcm = 0x02;
constexpr uint8_t kClassData = 0x0a;

uint8_t transfer_type(const libusb_endpoint_descriptor& endpoint) {
  return endpoint.bmAttributes & LIBUSB_TRANSFER_TYPE_MASK;
}
bool is_in(const libusb_endpoint_descriptor& endpoint) {
  return (endpoint.bEndpointAddress & LIBUSB_ENDPOINT_DIR_MASK) == LIBUSB_ENDPOINT_IN;
}

}  // namespace

std::variant<Layout, std::string> find_layout(const libusb_config_descriptor& config) {
  std::optional<Layout> control, data;
  for (int i = 0; i < config.bNumInterfaces; ++i) {
    const libusb_interface& interface = config.interface[i];
    if (interface.num_altsetting < 1) continue;
    // The serial port lives in the default alternate setting.
    const libusb_interface_descriptor& alt = interface.altsetting[0];
    if (alt.bInterfaceClass == kClassCommunications && alt.bInterfaceSubClass == kSubclassAcm && !control) {
      for (int e = 0; e < alt.bNumEndpoints; ++e) {
        const libusb_endpoint_descriptor& endpoint = alt.endpoint[e];
        if (transfer_type(endpoint) == LIBUSB_TRANSFER_TYPE_INTERRUPT && is_in(endpoint)) {
          control = Layout{};
          control->control_interface = alt.bInterfaceNumber;
          control->notification_endpoint = endpoint.bEndpointAddress;
          break;
        }
      }
    } else if (alt.bInterfaceClass == kClassData && !data) {
      Layout candidate;
      candidate.data_interface = alt.bInterfaceNumber;
      for (int e = 0; e < alt.bNumEndpoints; ++e) {
        const libusb_endpoint_descriptor& endpoint = alt.endpoint[e];
        if (transfer_type(endpoint) != LIBUSB_TRANSFER_TYPE_BULK) continue;
        if (is_in(endpoint) && !candidate.bulk_in) {
          candidate.bulk_in = endpoint.bEndpointAddress;
          candidate.bulk_in_max_packet = endpoint.wMaxPacketSize;
        } else if (!is_in(endpoint) && !candidate.bulk_out) {
          candidate.bulk_out = endpoint.bEndpointAddress;
        }
      }
      if (candidate.bulk_in && candidate.bulk_out && candidate.bulk_in_max_packet > 0) data = candidate;
    }
  }
  if (!control) {
    return std::string("no CDC-ACM control interface (class 0x02, subclass 0x02) with an interrupt IN endpoint");
  }
  if (!data) return std::string("no CDC data interface (class 0x0A) with a bulk IN and a bulk OUT endpoint");
  Layout layout = *data;
  layout.control_interface = control->control_interface;
  layout.notification_endpoint = control->notification_endpoint;
  return layout;
}

std::array<uint8_t, 7> line_coding_8n1(uint32_t baud) {
  return {uint8_t(baud), uint8_t(baud >> 8), uint8_t(baud >> 16), uint8_t(baud >> 24), 0, 0, 8};
}

}  // namespace rt::motor::cdc
