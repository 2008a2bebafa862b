#pragma once
// The motor on an Arduino Uno (devices/motor/firmware) over its 16U2 USB bridge, through
// libusb: no tty, no kernel serial settings to get wrong, and the same code whether or not
// cdc_acm is loaded (it is detached from the board while the motor is open).
//
// Opening resets the board on purpose: DTR is dropped and asserted (SET_CONTROL_LINE_STATE),
// which on the Uno pulses the ATmega's reset line, and the driver waits for the firmware's
// READY line. That costs about 1.5 s per (re)connection but gives a known state every time:
// motor off, empty line buffer, and proof that the board runs this protocol's firmware. Never
// asserting DTR would avoid the reset but leave the driver guessing what the board is doing;
// and any serial terminal that touched the port has reset it anyway.
//
// Unplugging never crashes: the command in flight fails with a message saying so, the
// connection is closed, and the next command reopens it (retries spaced by an exponential
// backoff while the board is missing). Not thread-safe: one thread (the touch loop's) owns it.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "motor/motor.h"

namespace rt::motor {

struct UsbMotorOptions {
  uint16_t vendor_id = 0x2341;   // Arduino
  uint16_t product_id = 0x0043;  // Uno R3 (16U2 USB-serial bridge)
  uint32_t baud = 115200;        // the firmware's UART rate

  std::chrono::milliseconds write_timeout{100};
  std::chrono::milliseconds reply_timeout{250};
  // From reset to READY: the Uno's bootloader waits about 1 s for an upload first.
  std::chrono::milliseconds ready_timeout{3000};
  // After a timeout or garbage, input is read until it stays quiet this long before the next
  // command, so a late reply is not taken for the answer to the next command.
  std::chrono::milliseconds drain_quiet{20};
  std::chrono::milliseconds retry_initial{100};
  std::chrono::milliseconds retry_max{2000};

  // Where status lines go (connected, unplugged, reconnect failed); default: stderr.
  std::function<void(const std::string&)> log;
};

class UsbMotor final : public Motor {
 public:
  // Starts libusb; throws std::invalid_argument for options that make no sense and
  // std::runtime_error when libusb cannot start, both saying why. Does not need the board to
  // be present: commands connect on demand.
  explicit UsbMotor(UsbMotorOptions options = {});
  // Sends a last stop (best effort) and gives the port back to the kernel driver.
  ~UsbMotor() override;
  UsbMotor(const UsbMotor&) = delete;
  UsbMotor& operator=(const UsbMotor&) = delete;

  // Opens the board now, ignoring the retry backoff; ok when already open.
  MotorStatus connect();
  bool connected() const;
  // What the board said at start, e.g. "remotetouch-motor 1"; empty while not connected.
  std::string firmware() const;

  MotorStatus pulse(std::chrono::milliseconds duration, int strength) override;
  MotorStatus stop() override;
  // Asks the board for its version line (e.g. "remotetouch-motor 1").
  MotorStatus query_version(std::string& version);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace rt::motor
