#pragma once
// Runs `work(k)` for every camera k on up to `threads` threads, the caller's among them: each
// camera's device or reader and its decoder are its own, so cameras wait and decode side by side.
// A camera's failure is rethrown once every camera is done, so that no thread is left running.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace rt::camera {

template <typename Work>
void for_each_camera_in_parallel(size_t count, unsigned threads, Work&& work) {
  std::atomic<size_t> next_camera{0};
  std::vector<std::exception_ptr> failures(count);
  const auto run = [&] {
    for (size_t k; (k = next_camera++) < count;) {
      try {
        work(k);
      } catch (...) {
        failures[k] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> helpers;
  for (size_t t = 1; t < std::min<size_t>(threads, count); ++t) helpers.emplace_back(run);
  run();
  for (std::thread& helper : helpers) helper.join();
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);
}

}  // namespace rt::camera
