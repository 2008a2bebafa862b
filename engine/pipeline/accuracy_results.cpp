#include "pipeline/accuracy_results.h"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "config/json.h"

namespace rt::pipeline {

namespace {

const std::vector<std::string> kMeasuredColumns = {"scenes",     "frames",  "psnr_fg_db", "psnr_hand_db",
                                                   "depth_mae_edge_mm", "alpha_iou", "gpu_ms", "gpu_ms_q1",
                                                   "gpu_ms_q3", "wall_s", "on_front", "on_front_hand"};

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream stream(line);
  while (std::getline(stream, cell, separator)) cells.push_back(cell);
  if (!line.empty() && line.back() == separator) cells.emplace_back();
  return cells;
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f", value);
  return text;
}

// A knob's CSV cell as the JSON value a config file would hold.
nlohmann::json knob_cell_json(const config::Knob<IbrSettings>& knob, const std::string& cell) {
  switch (knob.kind) {
    case config::KnobKind::Flag:
      if (cell != "true" && cell != "false") throw std::invalid_argument("not true or false");
      return cell == "true";
    case config::KnobKind::Choice:
    case config::KnobKind::Text: return cell;
    case config::KnobKind::Integer: return int64_t(std::stoll(cell));
    case config::KnobKind::Real: return std::stod(cell);
  }
  return nullptr;
}

// Better or equal in both, better in one.
bool beats(double accuracy_a, double ms_a, double accuracy_b, double ms_b) {
  return accuracy_a >= accuracy_b && ms_a <= ms_b && (accuracy_a > accuracy_b || ms_a < ms_b);
}

}  // namespace

std::vector<std::string> accuracy_csv_columns() {
  std::vector<std::string> columns = {"options"};
  for (const auto& knob : ibr_knobs()) columns.push_back(config::knob_json_key(knob.name));
  columns.insert(columns.end(), {"resolution_scale", "width", "height"});
  columns.insert(columns.end(), kMeasuredColumns.begin(), kMeasuredColumns.end());
  return columns;
}

void write_accuracy_csv(const std::filesystem::path& path, const std::vector<AccuracyRow>& rows) {
  const std::filesystem::path partial = path.string() + ".partial";
  {
    std::ofstream out(partial);
    if (!out) throw std::runtime_error("cannot write " + partial.string());
    const std::vector<std::string> columns = accuracy_csv_columns();
    for (size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c];
    out << "\n";
    for (const AccuracyRow& row : rows) {
      out << row.options;
      for (const auto& knob : ibr_knobs()) out << "," << config::knob_word(knob, row.ibr);
      out << "," << config::format_number(row.resolution_scale) << "," << row.ibr.width << "," << row.ibr.height << ","
          << row.scenes << "," << row.frames;
      for (double value : {row.psnr_fg_db, row.psnr_hand_db, row.depth_mae_edge_mm, row.alpha_iou, row.gpu_ms,
                           row.gpu_ms_q1, row.gpu_ms_q3, row.wall_s})
        out << "," << number(value);
      out << "," << int(row.on_front) << "," << int(row.on_front_hand) << "\n";
    }
    if (!out) throw std::runtime_error("cannot write " + partial.string());
  }
  std::filesystem::rename(partial, path);
}

std::vector<AccuracyRow> read_accuracy_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open '" + path.string() + "'");
  const std::vector<std::string> columns = accuracy_csv_columns();
  std::string line;
  std::getline(in, line);
  if (split(line, ',') != columns) {
    std::string expected;
    for (const std::string& column : columns) expected += (expected.empty() ? "" : ",") + column;
    throw std::runtime_error(path.string() + ": line 1: not the columns of bench accuracy's results.csv (expected " +
                             expected + ")");
  }
  std::vector<AccuracyRow> rows;
  for (size_t line_number = 2; std::getline(in, line); ++line_number) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = split(line, ',');
    const std::string where = path.string() + ": line " + std::to_string(line_number);
    if (cells.size() != columns.size())
      throw std::runtime_error(where + ": " + std::to_string(cells.size()) + " cells, expected " +
                               std::to_string(columns.size()));
    std::map<std::string, std::string> cell;
    for (size_t c = 0; c < columns.size(); ++c) cell[columns[c]] = cells[c];
    AccuracyRow row;
    std::string column;
    try {
      row.options = cell["options"];
      nlohmann::json knobs = nlohmann::json::object();
      for (const auto& knob : ibr_knobs()) {
        column = config::knob_json_key(knob.name);
        knobs[column] = knob_cell_json(knob, cell[column]);
      }
      column = "the knobs";
      config::read_knobs_json(ibr_knobs(), knobs, row.ibr, where);
      auto real = [&](const char* name) {
        column = name;
        const double value = std::stod(cell[name]);
        if (!std::isfinite(value)) throw std::invalid_argument("not finite");
        return value;
      };
      row.resolution_scale = real("resolution_scale");
      row.ibr.width = uint32_t(real("width"));
      row.ibr.height = uint32_t(real("height"));
      row.scenes = cell["scenes"];
      row.frames = uint32_t(real("frames"));
      row.psnr_fg_db = real("psnr_fg_db");
      row.psnr_hand_db = real("psnr_hand_db");
      row.depth_mae_edge_mm = real("depth_mae_edge_mm");
      row.alpha_iou = real("alpha_iou");
      row.gpu_ms = real("gpu_ms");
      row.gpu_ms_q1 = real("gpu_ms_q1");
      row.gpu_ms_q3 = real("gpu_ms_q3");
      row.wall_s = real("wall_s");
      row.on_front = real("on_front") != 0;
      row.on_front_hand = real("on_front_hand") != 0;
    } catch (const config::JsonError& error) {
      throw std::runtime_error(error.what());
    } catch (const std::exception&) {
      throw std::runtime_error(where + ": column " + column + ": cannot read '" + cell[column] + "'");
    }
    rows.push_back(row);
  }
  return rows;
}

void mark_fronts(std::vector<AccuracyRow>& rows) {
  for (AccuracyRow& row : rows) {
    row.on_front = row.on_front_hand = true;
    for (const AccuracyRow& other : rows) {
      if (&other == &row) continue;
      if (beats(other.psnr_fg_db, other.gpu_ms, row.psnr_fg_db, row.gpu_ms)) row.on_front = false;
      if (beats(other.psnr_hand_db, other.gpu_ms, row.psnr_hand_db, row.gpu_ms)) row.on_front_hand = false;
    }
  }
}

const AccuracyRow& most_accurate_within(const std::vector<AccuracyRow>& rows, double budget_ms, uint32_t width,
                                        uint32_t height, const std::string& where) {
  const AccuracyRow* best = nullptr;
  const AccuracyRow* fastest = nullptr;
  std::string sizes;
  for (const AccuracyRow& row : rows) {
    const std::string size = std::to_string(row.ibr.width) + "x" + std::to_string(row.ibr.height);
    if (sizes.find(size) == std::string::npos) sizes += (sizes.empty() ? "" : ", ") + size;
    if (row.ibr.width != width || row.ibr.height != height) continue;
    if (!fastest || row.gpu_ms < fastest->gpu_ms) fastest = &row;
    if (row.gpu_ms <= budget_ms && (!best || row.psnr_fg_db > best->psnr_fg_db)) best = &row;
  }
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (!fastest)
    throw std::runtime_error(where + ": no configuration measured at " + size + " (measured: " +
                             (sizes.empty() ? "none" : sizes) + "); run bench accuracy at that size");
  if (!best)
    throw std::runtime_error(where + ": nothing measured at " + size + " fits " + config::format_number(budget_ms) +
                             " GPU ms a frame; the fastest, '" + (fastest->options.empty() ? "the defaults" : fastest->options) +
                             "', takes " + number(fastest->gpu_ms) + " ms");
  return *best;
}

}  // namespace rt::pipeline
