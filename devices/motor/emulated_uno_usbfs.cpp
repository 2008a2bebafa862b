// The emulated Uno's answers to libusb's usbdevfs requests, as the kernel and the board would
// give them: URBs are queued and reaped, control requests configure the port, DTR resets the
// board, bulk OUT bytes run through the firmware's parser and its replies fill bulk IN URBs.
#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstring>

#include "motor/emulated_uno_state.h"

namespace rt::motor {
namespace {

constexpr const char* kSysPath = "/sys/devices/usb1";
constexpr uint8_t kClassInterfaceOut = 0x21;
constexpr uint8_t kSetLineCoding = 0x20;
constexpr uint8_t kSetControlLineState = 0x22;

uint64_t steady_now_us() {
  return uint64_t(
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count());
}

usbdevfs_urb* urb_of(UMockdevIoctlData* data) { return reinterpret_cast<usbdevfs_urb*>(data->data); }

}  // namespace

gboolean EmulatedUno::State::handle(UMockdevIoctlClient* client) {
  bool unplugged_now = false;
  {
    std::lock_guard lock(mutex);
    const gulong request = umockdev_ioctl_client_get_request(client);
    UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
    const bool current = plugged && devnode == umockdev_ioctl_client_get_devnode(client);
    if (request == USBDEVFS_REAPURB || request == USBDEVFS_REAPURBNDELAY) {
      reap(client, arg, current);
      return TRUE;
    }
    if (!current) {  // the kernel answers every request on a vanished device so
      umockdev_ioctl_client_complete(client, -1, ENODEV);
      return TRUE;
    }
    switch (request) {
      case USBDEVFS_GET_CAPABILITIES: {
        IoctlDataRef caps(umockdev_ioctl_data_resolve(arg, 0, sizeof(uint32_t), nullptr));
        *reinterpret_cast<uint32_t*>(caps->data) = USBDEVFS_CAP_BULK_CONTINUATION | USBDEVFS_CAP_NO_PACKET_SIZE_LIM |
                                              USBDEVFS_CAP_REAP_AFTER_DISCONNECT | USBDEVFS_CAP_ZERO_PACKET;
        umockdev_ioctl_client_complete(client, 0, 0);
        break;
      }
      case USBDEVFS_GETDRIVER: {
        IoctlDataRef driver(umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_getdriver), nullptr));
        auto* query = reinterpret_cast<usbdevfs_getdriver*>(driver->data);
        if (query->interface < 2 && bound[query->interface]) {
          std::snprintf(query->driver, sizeof query->driver, "cdc_acm");
          umockdev_ioctl_client_complete(client, 0, 0);
        } else {
          umockdev_ioctl_client_complete(client, -1, ENODATA);
        }
        break;
      }
      case USBDEVFS_IOCTL: {
        IoctlDataRef command(umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_ioctl), nullptr));
        auto* call = reinterpret_cast<usbdevfs_ioctl*>(command->data);
        const bool known = call->ifno >= 0 && call->ifno < 2;
        if (known && call->ioctl_code == int(USBDEVFS_DISCONNECT) && bound[call->ifno]) {
          bound[call->ifno] = false;
          events.push_back("detach " + std::to_string(call->ifno));
          umockdev_ioctl_client_complete(client, 0, 0);
        } else if (known && call->ioctl_code == int(USBDEVFS_CONNECT) && !bound[call->ifno]) {
          bound[call->ifno] = true;
          events.push_back("attach " + std::to_string(call->ifno));
          umockdev_ioctl_client_complete(client, 0, 0);
        } else {
          umockdev_ioctl_client_complete(client, -1, ENODATA);
        }
        break;
      }
      case USBDEVFS_CLAIMINTERFACE:
      case USBDEVFS_RELEASEINTERFACE: {
        IoctlDataRef number(umockdev_ioctl_data_resolve(arg, 0, sizeof(unsigned int), nullptr));
        const unsigned int interface = *reinterpret_cast<unsigned int*>(number->data);
        const bool claim = request == USBDEVFS_CLAIMINTERFACE;
        if (interface >= 2) {
          umockdev_ioctl_client_complete(client, -1, EINVAL);
        } else if (claim && bound[interface]) {
          umockdev_ioctl_client_complete(client, -1, EBUSY);  // cdc_acm still holds it
        } else {
          events.push_back((claim ? "claim " : "release ") + std::to_string(interface));
          umockdev_ioctl_client_complete(client, 0, 0);
        }
        break;
      }
      case USBDEVFS_SUBMITURB:
        submit(client, arg, &unplugged_now);
        break;
      case USBDEVFS_DISCARDURB:
        discard(client, arg);
        break;
      default: {
        char name[32];
        std::snprintf(name, sizeof name, "unhandled ioctl 0x%lx", request);
        events.push_back(name);
        umockdev_ioctl_client_complete(client, -1, ENOTTY);
      }
    }
  }
  if (unplugged_now) announce_removal();
  return TRUE;
}

void EmulatedUno::State::submit(UMockdevIoctlClient* client, UMockdevIoctlData* arg, bool* unplugged_now) {
  IoctlDataRef urb_data(umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), nullptr));
  usbdevfs_urb* urb = urb_of(urb_data.get());
  if (urb->buffer_length <= 0) {
    umockdev_ioctl_client_complete(client, -1, EINVAL);
    return;
  }
  IoctlDataRef buffer(umockdev_ioctl_data_resolve(urb_data.get(), offsetof(usbdevfs_urb, buffer),
                                                  size_t(urb->buffer_length), nullptr));
  const auto* bytes = buffer->data;
  urb->status = 0;
  urb->actual_length = 0;

  if (urb->type == USBDEVFS_URB_TYPE_CONTROL && urb->buffer_length >= 8) {
    control(urb, bytes);
    completed.push_back(std::move(urb_data));
  } else if (urb->type == USBDEVFS_URB_TYPE_BULK && urb->endpoint == descriptors.bulk_out) {
    outs.push_back(UsbBulkOut{steady_now_us(), std::string(reinterpret_cast<const char*>(bytes),
                                                           size_t(urb->buffer_length))});
    urb->actual_length = urb->buffer_length;
    completed.push_back(std::move(urb_data));
    firmware_receive(bytes, size_t(urb->buffer_length));
  } else if (urb->type == USBDEVFS_URB_TYPE_BULK && urb->endpoint == descriptors.bulk_in) {
    pending_in.push_back(std::move(urb_data));
    if (unplug_on_read) {
      unplug_on_read = false;
      disconnect();
      *unplugged_now = true;
    } else {
      deliver();
    }
  } else if (urb->type == USBDEVFS_URB_TYPE_INTERRUPT && urb->endpoint == descriptors.notification_endpoint) {
    pending_interrupt.push_back(std::move(urb_data));  // the 16U2 never sends serial state
  } else {
    char name[48];
    std::snprintf(name, sizeof name, "urb to unknown endpoint 0x%02x", unsigned(urb->endpoint));
    events.push_back(name);
    umockdev_ioctl_client_complete(client, -1, ENOENT);
    return;
  }
  umockdev_ioctl_client_complete(client, 0, 0);
}

void EmulatedUno::State::control(usbdevfs_urb* urb, const uint8_t* bytes) {
  UsbControlRequest request;
  request.request_type = bytes[0];
  request.request = bytes[1];
  request.value = uint16_t(bytes[2] | bytes[3] << 8);
  request.index = uint16_t(bytes[4] | bytes[5] << 8);
  const uint16_t length = uint16_t(bytes[6] | bytes[7] << 8);
  const bool out = (request.request_type & 0x80) == 0;
  if (out && 8 + length <= urb->buffer_length) request.data.assign(bytes + 8, bytes + 8 + length);
  controls.push_back(request);

  const bool to_control_interface = request.request_type == kClassInterfaceOut && request.index == 0;
  if (to_control_interface && request.request == kSetLineCoding && length == 7) {
    urb->actual_length = 7;
  } else if (to_control_interface && request.request == kSetControlLineState && length == 0) {
    // The Uno's reset line hangs off DTR through a capacitor: asserting DTR resets the ATmega.
    if (!(line_state & 0x01) && (request.value & 0x01)) reset_board();
    line_state = request.value;
  } else {
    urb->status = -EPIPE;  // a real device stalls requests it does not know
  }
}

void EmulatedUno::State::reap(UMockdevIoctlClient* client, UMockdevIoctlData* arg, bool current) {
  if (completed.empty()) {
    umockdev_ioctl_client_complete(client, -1, current ? EAGAIN : ENODEV);
    return;
  }
  IoctlDataRef urb_data = std::move(completed.front());
  completed.pop_front();
  IoctlDataRef pointer(umockdev_ioctl_data_resolve(arg, 0, sizeof(void*), nullptr));
  umockdev_ioctl_data_set_ptr(pointer.get(), 0, urb_data.get());
  umockdev_ioctl_client_complete(client, 0, 0);
}

void EmulatedUno::State::discard(UMockdevIoctlClient* client, UMockdevIoctlData* arg) {
  const auto address = gulong(*reinterpret_cast<void**>(arg->data));
  for (auto* queue : {&pending_in, &pending_interrupt}) {
    for (auto it = queue->begin(); it != queue->end(); ++it) {
      if ((*it)->client_addr != address) continue;
      urb_of(it->get())->status = -ENOENT;
      completed.push_back(std::move(*it));
      queue->erase(it);
      umockdev_ioctl_client_complete(client, 0, 0);
      return;
    }
  }
  umockdev_ioctl_client_complete(client, -1, EINVAL);
}

void EmulatedUno::State::firmware_receive(const uint8_t* bytes, size_t size) {
  for (size_t i = 0; i < size; ++i) {
    motor_command command;
    if (!motor_parser_feed(&parser, bytes[i], &command)) continue;
    if (command.kind == MOTOR_COMMAND_PULSE) strength = command.strength;
    if (command.kind == MOTOR_COMMAND_STOP) strength = 0;
    char reply[MOTOR_REPLY_MAX + 1];
    const size_t length = motor_format_reply(&command, reply, sizeof reply);
    if (replacement) {
      to_host += *replacement;
      replacement.reset();
    } else if (!silent) {
      to_host += std::string(reply, length) + "\n";
    }
  }
  deliver();
}

void EmulatedUno::State::reset_board() {
  ++resets;
  events.push_back("reset");
  motor_parser_reset(&parser);
  strength = 0;
  to_host.clear();
  if (!ready_line.empty()) to_host += ready_line + "\n";
  deliver();
}

void EmulatedUno::State::deliver() {
  while (!to_host.empty() && !pending_in.empty()) {
    IoctlDataRef urb_data = std::move(pending_in.front());
    pending_in.pop_front();
    usbdevfs_urb* urb = urb_of(urb_data.get());
    const size_t size = std::min(to_host.size(), size_t(urb->buffer_length));
    std::memcpy(urb->buffer, to_host.data(), size);
    to_host.erase(0, size);
    urb->actual_length = int(size);
    urb->status = 0;
    completed.push_back(std::move(urb_data));
  }
}

void EmulatedUno::State::disconnect() {
  plugged = false;
  events.push_back("unplug");
  for (auto* queue : {&pending_in, &pending_interrupt}) {
    for (IoctlDataRef& urb_data : *queue) {
      urb_of(urb_data.get())->status = -ESHUTDOWN;
      completed.push_back(std::move(urb_data));
    }
    queue->clear();
  }
}

void EmulatedUno::State::announce_removal() {
  umockdev_testbed_uevent(testbed, kSysPath, "remove");
  umockdev_testbed_remove_device(testbed, kSysPath);
}

}  // namespace rt::motor
