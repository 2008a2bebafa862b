#pragma once
// A settings struct's user-settable knobs as one table: each knob's name, help, kind (flag,
// integer, real, choice), range or choices and how to read and write it in the settings. The
// same table binds the command-line options (app/option_groups.h), reads a config file's object
// of them (JSON keys are the option names with '_' for '-'), writes the options a parent passes to
// a child process, and writes the settings as JSON (metrics files). So a new knob is one settings
// field plus one table row. CPU only.
#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "config/json.h"

namespace rt::config {

enum class KnobKind { Flag, Integer, Real, Choice, Text };

// Every knob's value but a Text knob's travels as a double: a flag 0 or 1, an integer, a real, a
// choice's index. A Text knob (a file name) has get_text and set_text instead of get and set.
template <class Settings>
struct Knob {
  using Get = std::function<double(const Settings&)>;
  using Set = std::function<void(Settings&, double)>;
  using GetText = std::function<std::string(const Settings&)>;
  using SetText = std::function<void(Settings&, const std::string&)>;
  // A constructor, not an aggregate, so that the tables' rows need not name the text accessors.
  Knob(std::string name, std::string help, KnobKind kind, double low, double high, std::vector<std::string> choices,
       Get get, Set set, GetText get_text = {}, SetText set_text = {})
      : name(std::move(name)),
        help(std::move(help)),
        kind(kind),
        low(low),
        high(high),
        choices(std::move(choices)),
        get(std::move(get)),
        set(std::move(set)),
        get_text(std::move(get_text)),
        set_text(std::move(set_text)) {}

  std::string name;  // the option's name without "--", e.g. "best-views"
  std::string help;
  KnobKind kind = KnobKind::Real;
  double low = 0, high = 0;          // Integer and Real: the accepted range, inclusive
  std::vector<std::string> choices;  // Choice: the accepted words
  Get get;
  Set set;
  GetText get_text;
  SetText set_text;
};

template <class Settings>
using KnobTable = std::vector<Knob<Settings>>;

// "best-views" -> "best_views".
inline std::string knob_json_key(const std::string& name) {
  std::string key = name;
  for (char& c : key)
    if (c == '-') c = '_';
  return key;
}

// The value as a command-line word: "9", "0.3", "avg"; a flag's "true"/"false".
template <class Settings>
std::string knob_text(const Knob<Settings>& knob, double value) {
  switch (knob.kind) {
    case KnobKind::Flag: return value != 0 ? "true" : "false";
    case KnobKind::Integer: return std::to_string(std::llround(value));
    case KnobKind::Choice: return knob.choices.at(size_t(value));
    case KnobKind::Real: break;
    case KnobKind::Text: throw std::logic_error("knob_text: --" + knob.name + " is text, use knob_word");
  }
  // A float setting prints as the float it is ("0.3", not "0.30000001192092896").
  if (double(float(value)) == value) {
    char text[32];
    const auto result = std::to_chars(text, text + sizeof text, float(value));
    return std::string(text, result.ptr);
  }
  return format_number(value);
}

template <class Settings>
nlohmann::json knob_json_value(const Knob<Settings>& knob, double value) {
  switch (knob.kind) {
    case KnobKind::Flag: return value != 0;
    case KnobKind::Integer: return std::llround(value);
    case KnobKind::Choice: return knob.choices.at(size_t(value));
    case KnobKind::Real: break;
    case KnobKind::Text: throw std::logic_error("knob_json_value: --" + knob.name + " is text");
  }
  if (double(float(value)) == value) return nlohmann::json::parse(knob_text(knob, value));
  return value;
}

// The knob's value in `settings` as a command-line word, whatever its kind.
template <class Settings>
std::string knob_word(const Knob<Settings>& knob, const Settings& settings) {
  return knob.kind == KnobKind::Text ? knob.get_text(settings) : knob_text(knob, knob.get(settings));
}

// The range or the choices, for help texts and errors: "in [0, 64]", "one of min, avg".
template <class Settings>
std::string knob_accepts(const Knob<Settings>& knob) {
  switch (knob.kind) {
    case KnobKind::Flag: return "true or false";
    case KnobKind::Choice: {
      std::string list;
      for (const std::string& choice : knob.choices) list += (list.empty() ? "" : ", ") + choice;
      return "one of " + list;
    }
    case KnobKind::Integer: return "an integer in [" + format_number(knob.low) + ", " + format_number(knob.high) + "]";
    case KnobKind::Real: break;
    case KnobKind::Text: return "a non-empty string";
  }
  return "a number in [" + format_number(knob.low) + ", " + format_number(knob.high) + "]";
}

// Every knob of `settings` as a JSON object (keys as in a config file).
template <class Settings>
nlohmann::json knobs_to_json(const KnobTable<Settings>& table, const Settings& settings) {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& knob : table)
    json[knob_json_key(knob.name)] =
        knob.kind == KnobKind::Text ? nlohmann::json(knob.get_text(settings)) : knob_json_value(knob, knob.get(settings));
  return json;
}

// Reads a config file's object of knobs into `settings` (knobs it does not name keep their
// values). `where` names the file and the object, e.g. "site.json: 'ibr'"; an unknown key, a
// value of the wrong type or out of range is a JsonError naming it and what is accepted.
template <class Settings>
void read_knobs_json(const KnobTable<Settings>& table, const nlohmann::json& object, Settings& settings,
                     const std::string& where) {
  if (!object.is_object()) throw JsonError(where + ": must be an object, not " + std::string(object.type_name()));
  for (const auto& [key, value] : object.items()) {
    const Knob<Settings>* knob = nullptr;
    for (const auto& candidate : table)
      if (knob_json_key(candidate.name) == key) knob = &candidate;
    if (!knob) {
      std::string list;
      for (const auto& candidate : table) list += (list.empty() ? "" : ", ") + knob_json_key(candidate.name);
      throw JsonError(where + ": unknown field '" + key + "' (known: " + list + ")");
    }
    // An array or object is named by its type, not dumped: dump() recurses, so a value nested a
    // hundred thousand deep (found by tests/fuzz/fuzz_site_config.cpp) overflowed the stack.
    const std::string shown = value.is_structured() ? std::string("an ") + value.type_name() : value.dump();
    const std::string wrong = where + ": field '" + key + "' must be " + knob_accepts(*knob) + ", is " + shown;
    double number = 0;
    switch (knob->kind) {
      case KnobKind::Flag:
        if (!value.is_boolean()) throw JsonError(wrong);
        number = value.template get<bool>() ? 1 : 0;
        break;
      case KnobKind::Choice: {
        if (!value.is_string()) throw JsonError(wrong);
        size_t index = 0;
        while (index < knob->choices.size() && knob->choices[index] != value.template get<std::string>()) ++index;
        if (index == knob->choices.size()) throw JsonError(wrong);
        number = double(index);
        break;
      }
      case KnobKind::Integer:
        if (!value.is_number_integer()) throw JsonError(wrong);
        number = double(value.template get<int64_t>());
        if (number < knob->low || number > knob->high) throw JsonError(wrong);
        break;
      case KnobKind::Real:
        if (!value.is_number()) throw JsonError(wrong);
        number = value.template get<double>();
        if (!std::isfinite(number) || number < knob->low || number > knob->high) throw JsonError(wrong);
        break;
      case KnobKind::Text:
        if (!value.is_string() || value.template get<std::string>().empty()) throw JsonError(wrong);
        knob->set_text(settings, value.template get<std::string>());
        continue;
    }
    knob->set(settings, number);
  }
}

// The command-line words that give a child process the knobs of `settings` that differ from
// `defaults`, e.g. {"--refine", "9", "--carve"}; `prefix` goes before each name ("hand-").
template <class Settings>
std::vector<std::string> knob_arguments(const KnobTable<Settings>& table, const Settings& settings,
                                        const Settings& defaults, const std::string& prefix = "") {
  std::vector<std::string> args;
  for (const auto& knob : table) {
    if (knob.kind == KnobKind::Text) {
      const std::string text = knob.get_text(settings);
      if (text != knob.get_text(defaults)) args.insert(args.end(), {"--" + prefix + knob.name, text});
      continue;
    }
    const double value = knob.get(settings);
    if (value == knob.get(defaults)) continue;
    if (knob.kind == KnobKind::Flag) {
      if (value != 0) args.push_back("--" + prefix + knob.name);
      continue;  // a flag set by default cannot be cleared on the command line
    }
    args.push_back("--" + prefix + knob.name);
    args.push_back(knob_text(knob, value));
  }
  return args;
}

}  // namespace rt::config
