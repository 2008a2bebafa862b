#pragma once
// The emulated Uno's state, shared by its public face (emulated_uno.cpp) and its usbdevfs
// handler (emulated_uno_usbfs.cpp). Private to those two files.
#include <umockdev.h>

#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "motor/emulated_uno.h"
#include "motor/firmware/protocol.h"

struct usbdevfs_urb;

namespace rt::motor {

struct IoctlDataUnref {
  void operator()(UMockdevIoctlData* data) const { g_object_unref(data); }
};
using IoctlDataRef = std::unique_ptr<UMockdevIoctlData, IoctlDataUnref>;

struct EmulatedUno::State {
  mutable std::mutex mutex;
  UMockdevTestbed* testbed = nullptr;
  UMockdevIoctlBase* handler = nullptr;

  UnoDescriptorOptions descriptors;
  int address = 0;
  std::string devnode;
  bool plugged = false;
  bool unplug_on_read = false;
  bool silent = false;
  std::string ready_line = "READY " MOTOR_FIRMWARE_NAME " 1";
  std::optional<std::string> replacement;

  bool bound[2] = {true, true};
  uint16_t line_state = 0;
  motor_parser parser{};
  uint8_t strength = 0;
  std::string to_host;  // sent by the board, not yet read by the host
  std::deque<IoctlDataRef> pending_in, pending_interrupt, completed;

  std::vector<UsbControlRequest> controls;
  std::vector<UsbBulkOut> outs;
  std::vector<std::string> events;
  int resets = 0;

  static gboolean on_ioctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer self) {
    return static_cast<State*>(self)->handle(client);
  }
  gboolean handle(UMockdevIoctlClient* client);
  void submit(UMockdevIoctlClient* client, UMockdevIoctlData* arg, bool* unplugged_now);
  void control(usbdevfs_urb* urb, const uint8_t* bytes);
  void reap(UMockdevIoctlClient* client, UMockdevIoctlData* arg, bool current);
  void discard(UMockdevIoctlClient* client, UMockdevIoctlData* arg);
  void firmware_receive(const uint8_t* bytes, size_t size);
  void reset_board();
  void deliver();
  void disconnect();
  void announce_removal();
};

}  // namespace rt::motor
