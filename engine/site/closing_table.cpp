#include "site/closing_table.h"

#include <cstdio>

namespace rt::site {

std::string table_cell(const nlohmann::json& value, const char* format) {
  if (!value.is_number()) return "-";
  char text[32];
  std::snprintf(text, sizeof text, format, value.get<double>());
  return text;
}

std::vector<std::pair<std::string, std::string>> closing_rows(const nlohmann::json& site) {
  std::vector<std::pair<std::string, std::string>> rows;
  // A path the metrics may lack (a site stopped early, a replayed site without a simulator).
  auto at = [&](const std::string& path) {
    const nlohmann::json::json_pointer pointer(path);
    return site.contains(pointer) ? site.at(pointer) : nlohmann::json();
  };
  auto count = [&](const std::string& path) { return table_cell(at(path), "%.0f"); };
  for (const char* stage : {"capture_to_portrait_on_screen", "skeleton_to_hand_on_screen", "touch_to_motor_command"})
    rows.emplace_back(std::string(stage) + " median ms", table_cell(at("/latency_ms/" + std::string(stage) + "/median_ms")));
  for (const char* stage : {"capture", "portraits_sent", "hand_renders", "display", "tracker", "touch_loop"})
    rows.emplace_back(std::string("fps ") + stage, table_cell(at("/fps/" + std::string(stage))));
  rows.emplace_back("frames displayed", count("/frames/displayed"));
  rows.emplace_back("frames dropped (capture / before ibr / display)", count("/frames/scene_frames_not_captured") + "/" +
                                                                           count("/frames/dropped_before_ibr") + "/" +
                                                                           count("/frames/dropped_before_display"));
  const nlohmann::json out_bytes = at("/bytes_per_s/out");
  rows.emplace_back("wire kB/s out",
                    table_cell(out_bytes.is_number() ? nlohmann::json(out_bytes.get<double>() / 1000.0) : nlohmann::json()));
  // Per stage: the frame graph's pass sums, and the wall time of the stage's GPU turn.
  const std::pair<const char*, const char*> stages[] = {{"simulator", "simulator_render_and_readback"},
                                                        {"ibr", "ibr_render_and_readback"},
                                                        {"hand", "hand_render"},
                                                        {"receiver", "receiver_render_and_readback"}};
  std::string gpu, wall;
  for (const auto& [graph, turn] : stages) {
    gpu += (gpu.empty() ? "" : "/") + count("/gpu_ms/" + std::string(graph) + "/total");
    wall += (wall.empty() ? "" : "/") + count("/stage_wall_ms/" + std::string(turn) + "/median_ms");
  }
  rows.emplace_back("GPU ms sim/ibr/hand/receiver (pass sums)", gpu);
  rows.emplace_back("wall ms sim/ibr/hand/receiver (median turn)", wall);
  rows.emplace_back("skeleton to portrait gap median ms", table_cell(at("/latency_ms/skeleton_to_portrait_gap/median_ms")));
  rows.emplace_back("frames with mesh hand / none (skeleton gap)",
                    count("/frames/with_mesh_hand") + " / " + count("/frames/no_hand_skeleton_gap"));
  rows.emplace_back("touch starts / motor pulses", count("/touch/starts") + " / " + count("/touch/motor_pulses"));
  rows.emplace_back("contact to vibration median ms (truth)",
                    table_cell(at("/touch/contact_to_vibration_ms/median_ms")));
  // A peer that ended its session said so first: that close is not counted as lost.
  rows.emplace_back("connections lost / reconnects / touches resent",
                    count("/net/connections_lost") + " / " + count("/net/reconnects") + " / " + count("/net/touches_resent"));
  rows.emplace_back("voice kbit/s out (Opus) / frames lost", table_cell(at("/sound/voice/bitrate_kbps"), "%.1f") + " / " +
                                                                 count("/sound/voice/jitter/lost"));
  rows.emplace_back("echo return loss enhancement dB (after 2 s)", table_cell(at("/sound/echo/erle_db_after_2s"), "%.1f"));
  rows.emplace_back("voice latency - portrait latency ms (median)", table_cell(at("/sound/voice_minus_portrait_ms"), "%.1f"));
  rows.emplace_back("touch sound onset - asked / - true contact ms",
                    table_cell(at("/sound/touch_sounds/sounds/0/late_ms"), "%.1f") + " / " +
                        table_cell(at("/sound/touch_sounds/sounds/0/onset_minus_true_contact_ms"), "%.1f"));
  const nlohmann::json state = at("/appearance/state");
  const nlohmann::json fitted = at("/appearance/frames_fitted");
  rows.emplace_back("appearance adaption (frames fitted)",
                    !state.is_string() ? "-"
                                       : state.get<std::string>() + (fitted.is_number() ? " (" + count("/appearance/frames_fitted") + ")" : ""));
  const nlohmann::json source = at("/viewpoint/source");
  rows.emplace_back("eye source", source.is_string() ? source.get<std::string>() : "-");
  const nlohmann::json eye_error = at("/viewpoint/error_against_true_eye");
  rows.emplace_back("eye error vs true eye mm (median / p95)",
                    eye_error.is_object() ? table_cell(eye_error.value("median_mm", nlohmann::json())) + " / " +
                                                table_cell(eye_error.value("p95_mm", nlohmann::json()))
                                          : "-");
  return rows;
}

void print_table_row(const std::string& name, const std::vector<std::string>& cells) {
  std::printf("%-48s", name.c_str());
  for (const std::string& cell : cells) std::printf(" %14s", cell.c_str());
  std::printf("\n");
}

}  // namespace rt::site
