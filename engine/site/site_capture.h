#pragma once
// RenderDoc captures of a running site (`site --capture-frame N`): one iteration of the sender's
// graph (the image-based model rendering its N-th portrait) and one of the receiver's (the hand
// and the compositing of the N-th portrait it shows), each titled, in the site's capture/ folder.
// Each stage's iteration runs inside its GPU turn, so other threads' work stays out of it.
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "pipeline/gpu_session.h"

namespace rt::site {

class SiteCapture {
 public:
  enum class Stage { Sender, Receiver };
  // frame < 0: nothing is captured.
  SiteCapture(pipeline::GpuSession& gpu, int frame, std::string site_name);

  // Captures from its construction to its end when `iteration` is the stage's frame to capture.
  class Scope {
   public:
    Scope(Scope&& other) noexcept : owner_(std::exchange(other.owner_, nullptr)), stage_(other.stage_) {}
    Scope(const Scope&) = delete;
    ~Scope();

   private:
    friend class SiteCapture;
    Scope(SiteCapture* owner, Stage stage) : owner_(owner), stage_(stage) {}
    SiteCapture* owner_;
    Stage stage_;
  };
  [[nodiscard]] Scope scope(Stage stage, uint64_t iteration);

  // {"frame", "sender", "receiver"} (each the .rdc path, or null), "not_taken" saying why.
  nlohmann::json to_json() const;
  // A line per stage: where the capture is, or why none was taken.
  void report() const;

 private:
  std::string title(Stage stage) const;
  pipeline::GpuSession& gpu_;
  int frame_;
  std::string site_name_;
  mutable std::mutex mutex_;  // one capture at a time: RenderDoc records one frame at once
  std::optional<std::string> paths_[2];
};

}  // namespace rt::site
