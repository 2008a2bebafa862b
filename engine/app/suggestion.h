#pragma once
// "Did you mean": the nearest of the names a command knows to a word the user mistyped.
#include <string>
#include <vector>

namespace rt::app {

// The choice nearest to `given` by edit distance, or empty when none is near enough to be the
// same word mistyped (at most a third of its letters changed, and at least one allowed).
std::string nearest_choice(const std::string& given, const std::vector<std::string>& choices);

}  // namespace rt::app
