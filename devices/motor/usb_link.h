#pragma once
// One open session with the board: the device handle, its claimed interfaces and the line
// reader. Destroying it releases the interfaces, gives them back to the kernel driver and
// closes the device, in that order.
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "motor/cdc_acm.h"
#include "motor/reply_lines.h"
#include "motor/usb_handles.h"
#include "motor/usb_motor.h"

namespace rt::motor {

using Log = std::function<void(const std::string&)>;

class UsbLink {
 public:
  // Finds the board, claims its serial port, sets 8N1 at options.baud, resets the board through
  // DTR and waits for its READY line. The error says which step failed and how to fix it.
  static std::variant<std::unique_ptr<UsbLink>, std::string> open(libusb_context* context,
                                                                  const UsbMotorOptions& options, const Log& log);

  // Both return 0 or a libusb error code; *error says what went wrong in words.
  int write_line(std::string_view line, std::chrono::milliseconds timeout, std::string* error);
  // The next line within `timeout` (LIBUSB_ERROR_TIMEOUT when none came).
  int read_line(std::chrono::milliseconds timeout, ReplyLine* line, std::string* error);
  // Drops input until none arrives for `quiet` (or the device fails); returns what was dropped.
  std::vector<ReplyLine> drain(std::chrono::milliseconds quiet);

  const std::string& where() const { return where_; }      // "2341:0043 on bus 1 address 4"
  const std::string& firmware() const { return firmware_; }  // "remotetouch-motor 1"

 private:
  UsbLink() = default;
  std::string open_device(libusb_device* device, const Log& log);
  std::string configure_port(const UsbMotorOptions& options);
  std::string wait_for_ready(std::chrono::milliseconds timeout, const Log& log);
  int read_some(std::chrono::milliseconds timeout);

  usb::DeviceHandle handle_;
  std::vector<usb::ClaimedInterface> claimed_;  // after handle_: released before it closes
  cdc::Layout layout_;
  ReplyLines lines_;
  std::vector<uint8_t> packet_;
  std::string where_;
  std::string firmware_;
};

}  // namespace rt::motor
