#include "audio/gst_audio.h"

#include <gst/app/gstappsrc.h>

#include <map>
#include <mutex>
#include <stdexcept>

namespace rt::audio {
namespace {

// The Debian package of each element the audio backends use.
const char* debian_package_of(const std::string& element) {
  static const std::map<std::string, const char*> packages = {
      {"appsrc", "gstreamer1.0-plugins-base"},        {"appsink", "gstreamer1.0-plugins-base"},
      {"audioconvert", "gstreamer1.0-plugins-base"},  {"audioresample", "gstreamer1.0-plugins-base"},
      {"wavparse", "gstreamer1.0-plugins-good"},      {"wavenc", "gstreamer1.0-plugins-good"},
      {"pulsesrc", "gstreamer1.0-pulseaudio"},        {"pulsesink", "gstreamer1.0-pulseaudio"},
      {"webrtcdsp", "gstreamer1.0-plugins-bad"},      {"webrtcechoprobe", "gstreamer1.0-plugins-bad"},
      {"filesrc", "libgstreamer1.0-0"},               {"filesink", "libgstreamer1.0-0"},
      {"qtdemux", "gstreamer1.0-plugins-good"},       {"mp4mux", "gstreamer1.0-plugins-good"},
      {"mpeg4videoparse", "gstreamer1.0-plugins-bad"}, {"avenc_aac", "gstreamer1.0-libav"}};
  const auto it = packages.find(element);
  return it == packages.end() ? "the GStreamer plugins (scripts/packages.txt)" : it->second;
}

std::string take_error(GstMessage* message) {
  GError* error = nullptr;
  gchar* debug = nullptr;
  gst_message_parse_error(message, &error, &debug);
  std::string text = error ? error->message : "unknown GStreamer error";
  if (GST_MESSAGE_SRC(message)) text = std::string(GST_OBJECT_NAME(GST_MESSAGE_SRC(message))) + ": " + text;
  if (error) g_error_free(error);
  g_free(debug);
  return text;
}

}  // namespace

void ensure_gstreamer() {
  static std::once_flag once;
  std::call_once(once, [] { gst_init(nullptr, nullptr); });
}

std::string missing_audio_elements(std::initializer_list<const char*> elements) {
  ensure_gstreamer();
  std::string missing;
  for (const char* name : elements) {
    GstElementFactory* factory = gst_element_factory_find(name);
    if (factory) {
      gst_object_unref(factory);
      continue;
    }
    missing += std::string(missing.empty() ? "" : "; ") + "the GStreamer element " + name +
               " is missing: apt-get install " + debian_package_of(name);
  }
  return missing;
}

GstElement* parse_pipeline(const std::string& description) {
  ensure_gstreamer();
  GError* error = nullptr;
  GstElement* pipeline = gst_parse_launch(description.c_str(), &error);
  if (error) {
    const std::string why = error->message;
    g_error_free(error);
    if (pipeline) gst_object_unref(pipeline);
    throw std::runtime_error("cannot build the audio pipeline '" + description + "': " + why);
  }
  return pipeline;
}

std::string pending_bus_error(GstElement* pipeline) {
  GstBus* bus = gst_element_get_bus(pipeline);
  std::string text;
  if (GstMessage* message = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR)) {
    text = take_error(message);
    gst_message_unref(message);
  }
  gst_object_unref(bus);
  return text;
}

std::string start_pipeline(GstElement* pipeline, std::chrono::milliseconds timeout) {
  const GstStateChangeReturn change = gst_element_set_state(pipeline, GST_STATE_PLAYING);
  std::string error = pending_bus_error(pipeline);
  if (!error.empty()) return error;
  if (change == GST_STATE_CHANGE_FAILURE) return "the pipeline would not start";
  if (change == GST_STATE_CHANGE_ASYNC) {
    GstState state = GST_STATE_NULL;
    const GstStateChangeReturn done = gst_element_get_state(pipeline, &state, nullptr, GST_MSECOND * timeout.count());
    error = pending_bus_error(pipeline);
    if (!error.empty()) return error;
    if (done == GST_STATE_CHANGE_FAILURE) return "the pipeline failed while starting";
    // Still ASYNC: a live source prerolls only once it has data; it is running.
  }
  return {};
}

namespace {

// Waits for the end of stream or an error, then stops the pipeline: empty, or what went wrong.
std::string wait_for_end_and_stop(GstElement* pipeline, std::chrono::milliseconds timeout, std::string error) {
  GstBus* bus = gst_element_get_bus(pipeline);
  if (error.empty()) {
    GstMessage* message = gst_bus_timed_pop_filtered(bus, GST_MSECOND * timeout.count(),
                                                     GstMessageType(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
    if (!message)
      error = "the pipeline did not finish within " + std::to_string(timeout.count()) + " ms";
    else if (GST_MESSAGE_TYPE(message) == GST_MESSAGE_ERROR)
      error = take_error(message);
    if (message) gst_message_unref(message);
  }
  gst_object_unref(bus);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  return error;
}

}  // namespace

std::string drain_and_stop(GstElement* pipeline, GstElement* source, std::chrono::milliseconds timeout) {
  const bool refused = gst_app_src_end_of_stream(GST_APP_SRC(source)) != GST_FLOW_OK;
  return wait_for_end_and_stop(pipeline, timeout, refused ? "the pipeline refused its end of stream" : "");
}

std::string run_to_end(GstElement* pipeline, std::chrono::milliseconds timeout) {
  return wait_for_end_and_stop(pipeline, timeout, start_pipeline(pipeline, std::chrono::milliseconds(0)));
}

}  // namespace rt::audio
