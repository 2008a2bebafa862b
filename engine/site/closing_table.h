#pragma once
// The table a run ends with: one row per figure, one column per site, each cell read from the
// site's metrics.json. `remotetouch site` prints its own column; the demo prints both sites'
// side by side and adds the rows only it can measure (the composites against the truth).
#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace rt::site {

// A number as the table shows it ("-" where the metrics have none).
std::string table_cell(const nlohmann::json& value, const char* format = "%.1f");

// The rows of one site's column: (row name, cell), in the table's order.
std::vector<std::pair<std::string, std::string>> closing_rows(const nlohmann::json& site_metrics);

// One line: the row name, then each column's cell.
void print_table_row(const std::string& name, const std::vector<std::string>& cells);

}  // namespace rt::site
