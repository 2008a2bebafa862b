#pragma once
// An Arduino Uno (16U2 bridge, 2341:0043) running the motor firmware, emulated under umockdev:
// the board appears in a umockdev test bed's sysfs with the real descriptors, and an ioctl
// handler answers libusb's usbdevfs requests the way the kernel and the board would. Bulk OUT
// bytes go through the firmware's own parser (firmware/protocol.c), so replies are what the
// board would send. It lets UsbMotor run unchanged without hardware: in the tests, and in a
// demo that wants the real driver path. The process must run under umockdev-wrapper.
//
// The handler runs on umockdev's worker thread; every method here is thread-safe.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rt::motor {

struct UnoDescriptorOptions {
  uint8_t notification_endpoint = 0x82;  // the stock 16U2 firmware's endpoints
  uint8_t bulk_out = 0x04;
  uint8_t bulk_in = 0x83;
  bool data_interface = true;  // false: a broken or foreign device without the CDC data interface
};

// Device descriptor and configuration descriptor, as sysfs "descriptors" holds them, in hex.
std::string uno_descriptors_hex(const UnoDescriptorOptions& options = {});

struct UsbControlRequest {
  uint8_t request_type = 0;
  uint8_t request = 0;
  uint16_t value = 0;
  uint16_t index = 0;
  std::vector<uint8_t> data;
};

struct UsbBulkOut {
  uint64_t submitted_us = 0;  // steady_clock microseconds when the URB reached the "device"
  std::string bytes;
};

class EmulatedUno {
 public:
  // Creates the test bed; throws std::runtime_error when not under umockdev-wrapper.
  EmulatedUno();
  ~EmulatedUno();
  EmulatedUno(const EmulatedUno&) = delete;
  EmulatedUno& operator=(const EmulatedUno&) = delete;

  // Plugs the board in (again): a new device address, as a real replug gives, cdc_acm bound
  // to both interfaces, the firmware in reset until DTR is asserted.
  void plug(const UnoDescriptorOptions& descriptors = {});
  // Pulls the cable: URBs in flight complete with ESHUTDOWN, every later request on the old
  // device fails with ENODEV, and udev announces the removal.
  void unplug();
  // Unplugs at the moment the next bulk IN transfer is submitted, i.e. while the driver waits
  // for a reply.
  void unplug_on_next_read();
  bool plugged() const;

  // What the firmware prints after a reset; empty: nothing (a board without the firmware).
  void set_ready_line(std::string line);
  // The next reply is replaced by these raw bytes (garbage, a foreign reply, ...).
  void replace_next_reply(std::string bytes);
  // Sends these bytes now, unasked, as a board that resets or chatters would.
  void send_unasked(std::string bytes);
  // A silent board never answers commands (it still prints its READY line).
  void set_silent(bool silent);

  std::vector<UsbControlRequest> control_requests() const;
  std::vector<UsbBulkOut> bulk_outs() const;
  std::string received() const;  // every bulk OUT byte since plug()
  std::vector<std::string> events() const;  // "claim 0", "detach 1", "attach 0", "reset", ...
  bool kernel_driver_bound(int interface) const;
  int resets() const;  // DTR-triggered resets since plug()
  uint8_t motor_strength() const;  // PWM duty of the last accepted pulse, 0 after S or a reset

  struct State;  // public only so the C callback can reach it

 private:
  std::unique_ptr<State> state_;
};

}  // namespace rt::motor
