#include "motor/emulated_uno.h"

#include <cstdio>
#include <stdexcept>

#include "motor/emulated_uno_state.h"

namespace rt::motor {
namespace {

std::string take_error(GError* error) {
  std::string message = error ? error->message : "unknown error";
  if (error) g_error_free(error);
  return message;
}

}  // namespace

std::string uno_descriptors_hex(const UnoDescriptorOptions& options) {
  // As the stock Arduino-usbserial firmware of the Uno R3's 16U2 reports them: a CDC device
  // with an ACM control interface (header, ACM and union functional descriptors, interrupt
  // notification endpoint) and a data interface with two 64-byte bulk endpoints.
  const std::vector<uint8_t> device = {0x12, 0x01, 0x10, 0x01, 0x02, 0x00, 0x00, 0x08, 0x41,
                                       0x23, 0x43, 0x00, 0x01, 0x00, 0x01, 0x02, 0xdc, 0x01};
  std::vector<uint8_t> interfaces = {0x09, 0x04, 0x00, 0x00, 0x01, 0x02, 0x02, 0x01, 0x00,  // control
                                     0x05, 0x24, 0x00, 0x10, 0x01,                          // header
                                     0x04, 0x24, 0x02, 0x06,                                // ACM
                                     0x05, 0x24, 0x06, 0x00, 0x01,                          // union
                                     0x07, 0x05, options.notification_endpoint, 0x03, 0x08, 0x00, 0xff};
  if (options.data_interface) {
    interfaces.insert(interfaces.end(), {0x09, 0x04, 0x01, 0x00, 0x02, 0x0a, 0x00, 0x00, 0x00,  //
                                         0x07, 0x05, options.bulk_out, 0x02, 0x40, 0x00, 0x01,   //
                                         0x07, 0x05, options.bulk_in, 0x02, 0x40, 0x00, 0x01});
  }
  const size_t total = 9 + interfaces.size();
  std::vector<uint8_t> all = device;
  all.insert(all.end(), {0x09, 0x02, uint8_t(total), uint8_t(total >> 8), uint8_t(options.data_interface ? 2 : 1),
                         0x01, 0x00, 0xc0, 0x32});
  all.insert(all.end(), interfaces.begin(), interfaces.end());
  std::string hex;
  for (const uint8_t byte : all) {
    char digits[3];
    std::snprintf(digits, sizeof digits, "%02x", unsigned(byte));
    hex += digits;
  }
  return hex;
}

EmulatedUno::EmulatedUno() : state_(std::make_unique<State>()) {
  state_->testbed = umockdev_testbed_new();
  // Asked after the test bed exists: umockdev answers from whether /sys is the test bed's.
  if (!umockdev_in_mock_environment()) {
    g_object_unref(state_->testbed);
    throw std::runtime_error(
        "the emulated Uno needs umockdev's preload library: run this program under umockdev-wrapper");
  }
  state_->handler = umockdev_ioctl_base_new();
  g_signal_connect(state_->handler, "handle-ioctl", G_CALLBACK(&State::on_ioctl), state_.get());
}

EmulatedUno::~EmulatedUno() {
  g_signal_handlers_disconnect_by_data(state_->handler, state_.get());
  {
    std::lock_guard lock(state_->mutex);
    state_->pending_in.clear();
    state_->pending_interrupt.clear();
    state_->completed.clear();
  }
  g_object_unref(state_->handler);
  g_object_unref(state_->testbed);
}

void EmulatedUno::plug(const UnoDescriptorOptions& descriptors) {
  std::string description;
  {
    std::lock_guard lock(state_->mutex);
    if (state_->plugged) throw std::logic_error("the emulated Uno is already plugged in");
    State& s = *state_;
    ++s.address;
    char node[32];
    std::snprintf(node, sizeof node, "bus/usb/001/%03d", s.address);
    s.devnode = std::string("/dev/") + node;
    s.descriptors = descriptors;
    s.bound[0] = s.bound[1] = true;
    s.line_state = 0;
    motor_parser_reset(&s.parser);
    s.strength = 0;
    s.to_host.clear();
    s.pending_in.clear();
    s.pending_interrupt.clear();
    s.completed.clear();
    s.controls.clear();
    s.outs.clear();
    s.events.clear();
    s.resets = 0;
    s.plugged = true;
    description = std::string("P: /devices/usb1\nN: ") + node +
                  "\nE: SUBSYSTEM=usb\nE: DRIVER=usb\nE: BUSNUM=001\nE: DEVNUM=" + std::string(node + 12) +
                  "\nE: DEVNAME=" + s.devnode +
                  "\nE: DEVTYPE=usb_device\nA: bConfigurationValue=1\\n\nA: busnum=1\\n\nA: devnum=" +
                  std::to_string(s.address) + "\\n\nA: speed=12\\n\nH: descriptors=" +
                  uno_descriptors_hex(descriptors) + "\n";
  }
  // The handler is attached before the device appears, so an opener never finds it unanswered.
  GError* error = nullptr;
  if (!umockdev_testbed_attach_ioctl(state_->testbed, state_->devnode.c_str(), state_->handler, &error)) {
    throw std::runtime_error("cannot attach the emulated Uno's ioctl handler: " + take_error(error));
  }
  if (!umockdev_testbed_add_from_string(state_->testbed, description.c_str(), &error)) {
    throw std::runtime_error("cannot add the emulated Uno to the test bed: " + take_error(error));
  }
}

void EmulatedUno::unplug() {
  {
    std::lock_guard lock(state_->mutex);
    if (!state_->plugged) return;
    state_->disconnect();
  }
  state_->announce_removal();
}

void EmulatedUno::unplug_on_next_read() {
  std::lock_guard lock(state_->mutex);
  state_->unplug_on_read = true;
}

bool EmulatedUno::plugged() const {
  std::lock_guard lock(state_->mutex);
  return state_->plugged;
}

void EmulatedUno::set_ready_line(std::string line) {
  std::lock_guard lock(state_->mutex);
  state_->ready_line = std::move(line);
}

void EmulatedUno::replace_next_reply(std::string bytes) {
  std::lock_guard lock(state_->mutex);
  state_->replacement = std::move(bytes);
}

void EmulatedUno::send_unasked(std::string bytes) {
  std::lock_guard lock(state_->mutex);
  state_->to_host += bytes;
  state_->deliver();
}

void EmulatedUno::set_silent(bool silent) {
  std::lock_guard lock(state_->mutex);
  state_->silent = silent;
}

std::vector<UsbControlRequest> EmulatedUno::control_requests() const {
  std::lock_guard lock(state_->mutex);
  return state_->controls;
}

std::vector<UsbBulkOut> EmulatedUno::bulk_outs() const {
  std::lock_guard lock(state_->mutex);
  return state_->outs;
}

std::string EmulatedUno::received() const {
  std::lock_guard lock(state_->mutex);
  std::string all;
  for (const UsbBulkOut& out : state_->outs) all += out.bytes;
  return all;
}

std::vector<std::string> EmulatedUno::events() const {
  std::lock_guard lock(state_->mutex);
  return state_->events;
}

bool EmulatedUno::kernel_driver_bound(int interface) const {
  std::lock_guard lock(state_->mutex);
  return interface >= 0 && interface < 2 && state_->bound[interface];
}

int EmulatedUno::resets() const {
  std::lock_guard lock(state_->mutex);
  return state_->resets;
}

uint8_t EmulatedUno::motor_strength() const {
  std::lock_guard lock(state_->mutex);
  return state_->strength;
}

}  // namespace rt::motor
