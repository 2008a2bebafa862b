#pragma once
// Move-only owners of libusb objects, so that every early return on the error paths of
// opening the board releases what was taken, in the right order.
#include <libusb.h>

#include <memory>
#include <span>
#include <string>

namespace rt::motor::usb {

// "LIBUSB_ERROR_ACCESS (Access denied (insufficient permissions))"
std::string error_text(int code);

struct ContextDeleter {
  void operator()(libusb_context* context) const { libusb_exit(context); }
};
using Context = std::unique_ptr<libusb_context, ContextDeleter>;
// Throws std::runtime_error with libusb's reason when libusb cannot start.
Context make_context();

struct HandleDeleter {
  void operator()(libusb_device_handle* handle) const { libusb_close(handle); }
};
using DeviceHandle = std::unique_ptr<libusb_device_handle, HandleDeleter>;

struct ConfigDescriptorDeleter {
  void operator()(libusb_config_descriptor* config) const { libusb_free_config_descriptor(config); }
};
using ConfigDescriptor = std::unique_ptr<libusb_config_descriptor, ConfigDescriptorDeleter>;

// The devices attached now; holds a reference on each until destroyed.
class DeviceList {
 public:
  DeviceList() = default;
  // Returns a negative libusb error code on failure, else 0.
  int fill(libusb_context* context);
  std::span<libusb_device* const> devices() const { return {list_.get(), size_}; }

 private:
  struct Deleter {
    void operator()(libusb_device** list) const { libusb_free_device_list(list, 1); }
  };
  std::unique_ptr<libusb_device*, Deleter> list_;
  size_t size_ = 0;
};

// A claimed interface: released when destroyed, and handed back to the kernel driver that was
// detached from it, so that /dev/ttyACM* comes back once the motor is closed.
class ClaimedInterface {
 public:
  ClaimedInterface(libusb_device_handle* handle, int number, bool reattach_kernel_driver)
      : handle_(handle), number_(number), reattach_(reattach_kernel_driver) {}
  ClaimedInterface(ClaimedInterface&& other) noexcept;
  ClaimedInterface& operator=(ClaimedInterface&& other) noexcept;
  ClaimedInterface(const ClaimedInterface&) = delete;
  ClaimedInterface& operator=(const ClaimedInterface&) = delete;
  ~ClaimedInterface();

 private:
  void release();
  libusb_device_handle* handle_ = nullptr;
  int number_ = -1;
  bool reattach_ = false;
};

}  // namespace rt::motor::usb
