#pragma once
// The GStreamer plumbing the audio backends share: initialisation, a missing element named with
// the Debian package that brings it, and a pipeline started or stopped with its error as a sentence.
#include <gst/gst.h>

#include <chrono>
#include <string>

namespace rt::audio {

void ensure_gstreamer();

// Empty when every element is installed, else what is missing and how to install it.
std::string missing_audio_elements(std::initializer_list<const char*> elements);

// Parses `description` (gst_parse_launch syntax); throws std::runtime_error saying what failed.
GstElement* parse_pipeline(const std::string& description);

// Sets PLAYING and waits up to `timeout` until the pipeline runs or fails: empty, or the error the
// bus reported. A pipeline fed by an appsrc cannot preroll before its first buffer: give it 0.
std::string start_pipeline(GstElement* pipeline, std::chrono::milliseconds timeout);

// Sends end-of-stream through `source` (an appsrc) and waits for it at the sink, so that a file
// writer has written its header; then stops the pipeline. Empty, or what went wrong.
std::string drain_and_stop(GstElement* pipeline, GstElement* source, std::chrono::milliseconds timeout);

// Plays a pipeline whose sources end by themselves (files) to its end of stream, then stops it.
// Empty, or what went wrong.
std::string run_to_end(GstElement* pipeline, std::chrono::milliseconds timeout);
// The first error message on the bus, if any (empty otherwise); does not wait.
std::string pending_bus_error(GstElement* pipeline);

}  // namespace rt::audio
