#pragma once
// Move-only owner of one Vulkan object. Releasing it does not destroy it at once: the Context
// destroys it after the GPU has finished all work submitted before the release, so a resource
// can go out of scope while a frame that uses it is still in flight.
// The Context must outlive every Handle made from it.
#include <vulkan/vulkan.h>

#include <utility>

#include "vulkan/context.h"

namespace rt::vk {

// Defined for each handle type in handle.cpp.
template <typename T>
void destroy_object(const Context& context, T object);

template <typename T>
class Handle {
 public:
  Handle() = default;
  Handle(Context& context, T object) : context_(&context), object_(object) {}
  ~Handle() { reset(); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : context_(other.context_), object_(std::exchange(other.object_, T{})) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      context_ = other.context_;
      object_ = std::exchange(other.object_, T{});
    }
    return *this;
  }

  T get() const { return object_; }
  explicit operator bool() const { return object_ != T{}; }

  void reset() {
    if (object_ == T{}) return;
    const Context* context = context_;
    T object = std::exchange(object_, T{});
    context_->retire([context, object] { destroy_object(*context, object); });
  }

 private:
  Context* context_ = nullptr;
  T object_{};
};

}  // namespace rt::vk
