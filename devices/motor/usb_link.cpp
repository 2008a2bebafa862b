#include "motor/usb_link.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "motor/firmware/protocol.h"

namespace rt::motor {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

// libusb reads a timeout of 0 as "wait forever": a deadline that has just run out must still
// give a finite wait.
unsigned int libusb_timeout(milliseconds timeout) { return unsigned(std::max<int64_t>(1, timeout.count())); }

milliseconds remaining_until(Clock::time_point deadline) {
  return std::chrono::ceil<milliseconds>(deadline - Clock::now());
}

std::string hex(unsigned value, int digits) {
  char text[9];
  std::snprintf(text, sizeof text, "%0*x", digits, value);
  return text;
}

std::string usb_id(const UsbMotorOptions& options) {
  return hex(options.vendor_id, 4) + ":" + hex(options.product_id, 4);
}

}  // namespace

std::variant<std::unique_ptr<UsbLink>, std::string> UsbLink::open(libusb_context* context,
                                                                   const UsbMotorOptions& options, const Log& log) {
  usb::DeviceList list;
  if (const int result = list.fill(context); result < 0) return "cannot list USB devices: " + usb::error_text(result);
  std::vector<libusb_device*> matches;
  for (libusb_device* device : list.devices()) {
    libusb_device_descriptor descriptor;
    if (libusb_get_device_descriptor(device, &descriptor) == 0 && descriptor.idVendor == options.vendor_id &&
        descriptor.idProduct == options.product_id) {
      matches.push_back(device);
    }
  }
  if (matches.empty()) {
    return "no USB device " + usb_id(options) + " (Arduino Uno) is attached: is the motor's board plugged in?";
  }

  std::unique_ptr<UsbLink> link(new UsbLink());
  link->where_ = usb_id(options) + " on bus " + std::to_string(libusb_get_bus_number(matches[0])) + " address " +
                 std::to_string(libusb_get_device_address(matches[0]));
  if (matches.size() > 1) {
    log("found " + std::to_string(matches.size()) + " devices " + usb_id(options) + "; using the one " +
        link->where_.substr(usb_id(options).size() + 1));
  }
  std::string error = link->open_device(matches[0], log);
  if (error.empty()) error = link->configure_port(options);
  if (error.empty()) error = link->wait_for_ready(options.ready_timeout, log);
  if (!error.empty()) return link->where_ + ": " + error;
  return link;
}

std::string UsbLink::open_device(libusb_device* device, const Log& log) {
  libusb_config_descriptor* raw_config = nullptr;
  if (const int result = libusb_get_active_config_descriptor(device, &raw_config); result != 0) {
    return "cannot read its active configuration descriptor: " + usb::error_text(result);
  }
  const usb::ConfigDescriptor config(raw_config);
  auto found = cdc::find_layout(*config);
  if (const auto* why = std::get_if<std::string>(&found)) {
    return *why + ": is it an Arduino Uno with its stock USB-serial bridge firmware?";
  }
  layout_ = std::get<cdc::Layout>(found);
  packet_.resize(layout_.bulk_in_max_packet);

  libusb_device_handle* raw_handle = nullptr;
  if (const int result = libusb_open(device, &raw_handle); result != 0) {
    if (result == LIBUSB_ERROR_ACCESS) {
      return "permission denied opening it (" + usb::error_text(result) +
             "): install devices/motor/99-remotetouch-motor.rules as devices/motor/README.md describes";
    }
    return "cannot open it: " + usb::error_text(result);
  }
  handle_.reset(raw_handle);

  for (const int interface : {int(layout_.control_interface), int(layout_.data_interface)}) {
    const std::string name = "interface " + std::to_string(interface);
    bool detached = false;
    const int active = libusb_kernel_driver_active(handle_.get(), interface);
    if (active == 1) {
      if (const int result = libusb_detach_kernel_driver(handle_.get(), interface); result != 0) {
        return "cannot detach the kernel driver from " + name + ": " + usb::error_text(result);
      }
      detached = true;
      log(where_ + ": detached the kernel driver (cdc_acm) from " + name + "; it is given back on close");
    } else if (active < 0 && active != LIBUSB_ERROR_NOT_SUPPORTED) {
      return "cannot ask whether a kernel driver holds " + name + ": " + usb::error_text(active);
    }
    if (const int result = libusb_claim_interface(handle_.get(), interface); result != 0) {
      if (detached) libusb_attach_kernel_driver(handle_.get(), interface);
      if (result == LIBUSB_ERROR_BUSY) {
        return name + " is claimed by another program (a serial monitor? another RemoteTouch?): " +
               usb::error_text(result);
      }
      return "cannot claim " + name + ": " + usb::error_text(result);
    }
    claimed_.emplace_back(handle_.get(), interface, detached);
  }
  return {};
}

std::string UsbLink::configure_port(const UsbMotorOptions& options) {
  const unsigned int timeout = libusb_timeout(options.write_timeout);
  auto coding = cdc::line_coding_8n1(options.baud);
  int result = libusb_control_transfer(handle_.get(), cdc::kRequestTypeClassInterfaceOut, cdc::kSetLineCoding, 0,
                                       layout_.control_interface, coding.data(), uint16_t(coding.size()), timeout);
  if (result != int(coding.size())) {
    return "SET_LINE_CODING (" + std::to_string(options.baud) + " 8N1) failed: " +
           (result < 0 ? usb::error_text(result) : "sent " + std::to_string(result) + " of 7 bytes");
  }
  // Dropping DTR first makes the assertion an edge, so the board resets even when an earlier
  // session left DTR asserted; READY then proves the reset happened and the firmware runs.
  result = libusb_control_transfer(handle_.get(), cdc::kRequestTypeClassInterfaceOut, cdc::kSetControlLineState, 0,
                                   layout_.control_interface, nullptr, 0, timeout);
  if (result < 0) return "SET_CONTROL_LINE_STATE (DTR off) failed: " + usb::error_text(result);
  lines_.clear();
  result = libusb_control_transfer(handle_.get(), cdc::kRequestTypeClassInterfaceOut, cdc::kSetControlLineState,
                                   cdc::kControlLineDtr | cdc::kControlLineRts, layout_.control_interface, nullptr, 0,
                                   timeout);
  if (result < 0) return "SET_CONTROL_LINE_STATE (DTR on, resetting the board) failed: " + usb::error_text(result);
  return {};
}

std::string UsbLink::wait_for_ready(milliseconds timeout, const Log& log) {
  const auto deadline = Clock::now() + timeout;
  const std::string expected = "READY " MOTOR_FIRMWARE_NAME " " + std::to_string(MOTOR_PROTOCOL_VERSION);
  for (;;) {
    const milliseconds remaining = remaining_until(deadline);
    if (remaining.count() <= 0) {
      return "no '" + expected + "' line within " + std::to_string(timeout.count()) +
             " ms of resetting the board: is devices/motor/firmware flashed (devices/motor/README.md)?";
    }
    ReplyLine line;
    std::string error;
    const int result = read_line(remaining, &line, &error);
    if (result == LIBUSB_ERROR_TIMEOUT) continue;
    if (result != 0) return "waiting for the board's READY line: " + error;
    // A reset can leave half a line or line noise behind; only READY counts.
    if (!line.error.empty() || line.text.rfind("READY ", 0) != 0) {
      log(where_ + ": ignoring '" + quote_bytes(line.text) + "' before READY" +
          (line.error.empty() ? "" : " (" + line.error + ")"));
      continue;
    }
    std::istringstream words(line.text.substr(6));
    std::string name, version, extra;
    words >> name >> version;
    if (name != MOTOR_FIRMWARE_NAME || version.empty() || (words >> extra)) {
      return "it runs other firmware: it said '" + quote_bytes(line.text) + "' where '" + expected +
             "' was expected; flash devices/motor/firmware (devices/motor/README.md)";
    }
    if (version != std::to_string(MOTOR_PROTOCOL_VERSION)) {
      return "its firmware speaks protocol " + quote_bytes(version) + " but this driver speaks " +
             std::to_string(MOTOR_PROTOCOL_VERSION) + ": flash the firmware built from this source tree";
    }
    firmware_ = name + " " + version;
    return {};
  }
}

int UsbLink::read_some(milliseconds timeout) {
  int received = 0;
  const int result = libusb_bulk_transfer(handle_.get(), layout_.bulk_in, packet_.data(), int(packet_.size()),
                                          &received, libusb_timeout(timeout));
  // A transfer that times out may still have delivered bytes.
  if (received > 0) lines_.append(std::span<const uint8_t>(packet_.data(), size_t(received)));
  return result;
}

int UsbLink::read_line(milliseconds timeout, ReplyLine* line, std::string* error) {
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    if (auto next = lines_.next()) {
      *line = std::move(*next);
      return 0;
    }
    const milliseconds remaining = remaining_until(deadline);
    if (remaining.count() <= 0) {
      *error = "no complete line within " + std::to_string(timeout.count()) + " ms";
      return LIBUSB_ERROR_TIMEOUT;
    }
    const int result = read_some(remaining);
    if (result != 0 && result != LIBUSB_ERROR_TIMEOUT) {
      *error = "reading bulk IN endpoint 0x" + hex(layout_.bulk_in, 2) + " failed: " + usb::error_text(result);
      return result;
    }
  }
}

int UsbLink::write_line(std::string_view line, milliseconds timeout, std::string* error) {
  std::string bytes(line);
  bytes.push_back('\n');
  int sent = 0;
  const int result = libusb_bulk_transfer(handle_.get(), layout_.bulk_out, reinterpret_cast<uint8_t*>(bytes.data()),
                                          int(bytes.size()), &sent, libusb_timeout(timeout));
  if (result != 0 || sent != int(bytes.size())) {
    *error = "sending '" + quote_bytes(line) + "' to bulk OUT endpoint 0x" + hex(layout_.bulk_out, 2) + " failed: " +
             (result != 0 ? usb::error_text(result) : std::string("short write")) + " after " +
             std::to_string(sent) + " of " + std::to_string(bytes.size()) + " bytes";
    return result != 0 ? result : LIBUSB_ERROR_IO;
  }
  return 0;
}

std::vector<ReplyLine> UsbLink::drain(milliseconds quiet) {
  std::vector<ReplyLine> dropped;
  // Bounded, so a device that never stops talking cannot hold the caller forever.
  const auto give_up = Clock::now() + 10 * quiet;
  for (;;) {
    while (auto line = lines_.next()) dropped.push_back(std::move(*line));
    if (Clock::now() >= give_up || read_some(quiet) != 0) break;
  }
  while (auto line = lines_.next()) dropped.push_back(std::move(*line));
  lines_.clear();
  return dropped;
}

}  // namespace rt::motor
