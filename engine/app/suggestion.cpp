#include "app/suggestion.h"

#include <algorithm>
#include <vector>

namespace rt::app {
namespace {

// Edit distance where swapping two neighbouring letters, the commonest slip, counts once
// (optimal string alignment).
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

}  // namespace

std::string nearest_choice(const std::string& given, const std::vector<std::string>& choices) {
  // No option or command is this long: a word this long is not one mistyped, and its table would
  // grow with it.
  if (given.size() > 64) return "";
  const size_t allowed = std::max<size_t>(1, given.size() / 3);
  std::string best;
  size_t best_distance = allowed + 1;
  for (const std::string& choice : choices) {
    const size_t distance = edit_distance(given, choice);
    if (distance < best_distance) {
      best = choice;
      best_distance = distance;
    }
  }
  return best;
}

}  // namespace rt::app
