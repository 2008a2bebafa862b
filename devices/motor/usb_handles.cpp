#include "motor/usb_handles.h"

#include <stdexcept>
#include <utility>

namespace rt::motor::usb {

std::string error_text(int code) {
  return std::string(libusb_error_name(code)) + " (" + libusb_strerror(code) + ")";
}

Context make_context() {
  libusb_context* context = nullptr;
  if (const int result = libusb_init(&context); result != 0) {
    throw std::runtime_error("cannot start libusb for the motor: " + error_text(result));
  }
  return Context(context);
}

int DeviceList::fill(libusb_context* context) {
  libusb_device** list = nullptr;
  const ssize_t count = libusb_get_device_list(context, &list);
  if (count < 0) return int(count);
  list_.reset(list);
  size_ = size_t(count);
  return 0;
}

ClaimedInterface::ClaimedInterface(ClaimedInterface&& other) noexcept
    : handle_(std::exchange(other.handle_, nullptr)), number_(other.number_), reattach_(other.reattach_) {}

ClaimedInterface& ClaimedInterface::operator=(ClaimedInterface&& other) noexcept {
  if (this != &other) {
    release();
    handle_ = std::exchange(other.handle_, nullptr);
    number_ = other.number_;
    reattach_ = other.reattach_;
  }
  return *this;
}

ClaimedInterface::~ClaimedInterface() { release(); }

void ClaimedInterface::release() {
  if (!handle_) return;
  // Both fail with LIBUSB_ERROR_NO_DEVICE after an unplug; there is nothing left to release.
  libusb_release_interface(handle_, number_);
  if (reattach_) libusb_attach_kernel_driver(handle_, number_);
  handle_ = nullptr;
}

}  // namespace rt::motor::usb
