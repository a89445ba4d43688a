#include "core/config.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace biota::core {
namespace {

const char* type_name(ConfigType t) {
  switch (t) {
    case ConfigType::kBool:
      return "boolean";
    case ConfigType::kInt:
      return "integer";
    case ConfigType::kReal:
      return "real";
    case ConfigType::kString:
      return "string";
    case ConfigType::kRealList:
      return "list of reals";
  }
  return "?";
}

std::string fmt_num(double v) {
  if (v == std::floor(v) && std::fabs(v) < 1e19) return fmt::format("{:.0f}", v);
  return fmt::format("{}", v);
}

/// Convert a TOML node to the declared type, or return nullopt if the type does not fit.
std::optional<ConfigValue> convert(const toml::node& node, ConfigType type) {
  switch (type) {
    case ConfigType::kBool:
      if (auto v = node.value_exact<bool>()) return ConfigValue{*v};
      return std::nullopt;
    case ConfigType::kInt:
      if (auto v = node.value_exact<std::int64_t>()) return ConfigValue{*v};
      return std::nullopt;
    case ConfigType::kReal:
      if (node.is_floating_point() || node.is_integer()) return ConfigValue{*node.value<double>()};
      return std::nullopt;
    case ConfigType::kString:
      if (auto v = node.value_exact<std::string>()) return ConfigValue{*v};
      return std::nullopt;
    case ConfigType::kRealList: {
      const auto* arr = node.as_array();
      if (!arr) return std::nullopt;
      std::vector<double> out;
      for (const auto& el : *arr) {
        if (!(el.is_floating_point() || el.is_integer())) return std::nullopt;
        out.push_back(*el.value<double>());
      }
      return ConfigValue{out};
    }
  }
  return std::nullopt;
}

std::string node_text(const toml::node& node) {
  if (node.is_floating_point()) return fmt::format("{}", *node.value<double>());
  std::ostringstream os;
  node.visit([&](auto&& n) { os << n; });
  return os.str();
}

void flatten(const toml::table& table, const std::string& prefix,
             std::vector<std::pair<std::string, const toml::node*>>& out) {
  for (const auto& [k, v] : table) {
    std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = v.as_table())
      flatten(*sub, key, out);
    else
      out.emplace_back(key, &v);
  }
}

}  // namespace

void ConfigSchema::add(const std::string& key, KeySpec spec) {
  if (spec.type == ConfigType::kInt && !(spec.min && spec.max))
    throw std::logic_error("config schema: integer key '" + key +
                           "' declared without a range; give both bounds");
  keys_[key] = std::move(spec);
}

void ConfigSchema::add_real(const std::string& key, std::optional<double> def,
                            std::optional<double> min, std::optional<double> max, std::string unit,
                            std::string doc, bool min_exclusive) {
  KeySpec s;
  s.type = ConfigType::kReal;
  if (def) s.default_value = *def;
  s.min = min;
  s.max = max;
  s.min_exclusive = min_exclusive;
  s.unit = std::move(unit);
  s.doc = std::move(doc);
  add(key, std::move(s));
}

void ConfigSchema::add_int(const std::string& key, std::optional<std::int64_t> def,
                           std::int64_t min, std::int64_t max, std::string doc) {
  KeySpec s;
  s.type = ConfigType::kInt;
  if (def) s.default_value = *def;
  s.min = static_cast<double>(min);
  s.max = static_cast<double>(max);
  s.unit = "-";
  s.doc = std::move(doc);
  add(key, std::move(s));
}

void ConfigSchema::add_bool(const std::string& key, bool def, std::string doc) {
  KeySpec s;
  s.type = ConfigType::kBool;
  s.default_value = def;
  s.unit = "-";
  s.doc = std::move(doc);
  add(key, std::move(s));
}

void ConfigSchema::add_string(const std::string& key, std::optional<std::string> def,
                              std::vector<std::string> choices, std::string doc) {
  KeySpec s;
  s.type = ConfigType::kString;
  if (def) s.default_value = *def;
  s.choices = std::move(choices);
  s.unit = "-";
  s.doc = std::move(doc);
  add(key, std::move(s));
}

void ConfigSchema::add_real_list(const std::string& key, std::optional<std::vector<double>> def,
                                 int length, std::string unit, std::string doc) {
  KeySpec s;
  s.type = ConfigType::kRealList;
  if (def) s.default_value = *def;
  s.list_length = length;
  s.unit = std::move(unit);
  s.doc = std::move(doc);
  add(key, std::move(s));
}

const KeySpec* ConfigSchema::find(const std::string& key) const {
  auto it = keys_.find(key);
  return it == keys_.end() ? nullptr : &it->second;
}

std::string describe_range(const KeySpec& s) {
  if (!s.choices.empty()) {
    std::string out = "one of {";
    for (size_t i = 0; i < s.choices.size(); ++i) out += (i ? ", " : "") + s.choices[i];
    return out + "}";
  }
  if (s.type == ConfigType::kRealList)
    return s.list_length > 0 ? fmt::format("list of {} reals", s.list_length) : "list of reals";
  if (s.type == ConfigType::kBool) return "true or false";
  if (s.type == ConfigType::kString) return "any string";
  std::string lo = s.min ? (s.min_exclusive ? "(" : "[") + fmt_num(*s.min) : "(-inf";
  std::string hi = s.max ? fmt_num(*s.max) + (s.max_exclusive ? ")" : "]") : "inf)";
  return lo + ", " + hi;
}

std::string to_toml_text(const ConfigValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool>)
          return x ? "true" : "false";
        else if constexpr (std::is_same_v<T, std::int64_t>)
          return fmt::format("{}", x);
        else if constexpr (std::is_same_v<T, double>) {
          std::string s = fmt::format("{}", x);
          if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
          return s;
        } else if constexpr (std::is_same_v<T, std::string>) {
          return "\"" + x + "\"";
        } else {
          std::string s = "[";
          for (size_t i = 0; i < x.size(); ++i) s += (i ? ", " : "") + fmt::format("{}", x[i]);
          return s + "]";
        }
      },
      v);
}

std::string ConfigSchema::reference_markdown() const {
  std::string out =
      "| key | type | default | allowed | unit | meaning |\n|---|---|---|---|---|---|\n";
  for (const auto& [k, s] : keys_) {
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", k, type_name(s.type),
                       s.default_value ? "`" + to_toml_text(*s.default_value) + "`" : "required",
                       describe_range(s), s.unit, s.doc);
  }
  return out;
}

namespace {

void check_value(const std::string& source, const std::string& key, const KeySpec& s,
                 const ConfigValue& v, const std::string& shown) {
  auto bad = [&](const std::string& why) {
    throw InputError(
        fmt::format("{}: {} = {} {}; allowed: {}", source, key, shown, why, describe_range(s)));
  };
  if (s.type == ConfigType::kInt) {
    // Compared as integers: above 2^53 a double cannot tell max from max + 1.
    const std::int64_t x = std::get<std::int64_t>(v);
    if (x < static_cast<std::int64_t>(*s.min) || x > static_cast<std::int64_t>(*s.max))
      bad("is out of range");
  }
  if (s.type == ConfigType::kReal) {
    const double x = std::get<double>(v);
    if (!std::isfinite(x)) bad("is not finite");
    if (s.min && (x < *s.min || (s.min_exclusive && x == *s.min))) bad("is out of range");
    if (s.max && (x > *s.max || (s.max_exclusive && x == *s.max))) bad("is out of range");
  }
  if (s.type == ConfigType::kString && !s.choices.empty()) {
    const auto& str = std::get<std::string>(v);
    bool ok = false;
    for (const auto& c : s.choices) ok = ok || c == str;
    if (!ok) bad("is not a known choice");
  }
  if (s.type == ConfigType::kRealList) {
    const auto& l = std::get<std::vector<double>>(v);
    if (s.list_length > 0 && static_cast<int>(l.size()) != s.list_length) bad("has wrong length");
    for (double x : l)
      if (!std::isfinite(x)) bad("contains a non-finite value");
  }
}

}  // namespace

std::string read_input_file(const std::string& path, const std::string& noun,
                            const std::string& unreadable) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(fmt::format("{}: is a directory, not {}", path, noun));
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: {}", path, unreadable));
  std::stringstream buf;
  buf << in.rdbuf();
  return buf.str();
}

std::string read_deck_text(const std::string& file) {
  return read_input_file(file, "a deck file", "cannot open deck (missing or unreadable file)");
}

std::string override_string_value(const std::string& value) {
  try {
    const auto t = toml::parse("v = " + value);
    if (auto s = t["v"].value<std::string>()) return *s;
  } catch (const toml::parse_error&) {
  }
  return value;
}

Config Config::from_file(const ConfigSchema& schema, const std::string& file,
                         const std::vector<std::string>& overrides) {
  return from_string(schema, read_deck_text(file), file, overrides);
}

Config Config::from_string(const ConfigSchema& schema, const std::string& text,
                           const std::string& source, const std::vector<std::string>& overrides) {
  Config cfg;
  cfg.schema_ = &schema;
  cfg.source_ = source;
  toml::table table;
  try {
    table = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", source, e.source().begin.line,
                                 e.source().begin.column, e.description()));
  }
  std::vector<std::pair<std::string, const toml::node*>> entries;
  flatten(table, "", entries);
  for (const auto& [key, node] : entries) {
    const KeySpec* spec = schema.find(key);
    if (!spec)
      throw InputError(
          fmt::format("{}: unknown key '{}' (see docs/deck-reference.md)", source, key));
    auto v = convert(*node, spec->type);
    if (!v)
      throw InputError(fmt::format("{}: {} = {} has the wrong type; expected {}: {}", source, key,
                                   node_text(*node), type_name(spec->type), describe_range(*spec)));
    check_value(source, key, *spec, *v, node_text(*node));
    cfg.values_[key] = {*v, true};
  }
  for (const auto& ov : overrides) {
    auto eq = ov.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError(fmt::format("--set {}: expected key=value", ov));
    std::string key = ov.substr(0, eq), val = ov.substr(eq + 1);
    const KeySpec* spec = schema.find(key);
    if (!spec) throw InputError(fmt::format("--set: unknown key '{}'", key));
    // Parse the value as TOML so that strings may be given bare or quoted.
    toml::table t;
    std::string line = "v = " + val;
    try {
      t = toml::parse(line);
    } catch (const toml::parse_error&) {
      try {
        t = toml::parse("v = \"" + val + "\"");
      } catch (const toml::parse_error&) {
        throw InputError(fmt::format("--set {}: cannot parse value '{}'", key, val));
      }
    }
    auto v = convert(*t.get("v"), spec->type);
    if (!v && spec->type == ConfigType::kString) v = ConfigValue{val};
    if (!v)
      throw InputError(fmt::format("--set {} = {} has the wrong type; expected {}: {}", key, val,
                                   type_name(spec->type), describe_range(*spec)));
    check_value("--set", key, *spec, *v, val);
    cfg.values_[key] = {*v, true};
  }
  for (const auto& [key, spec] : schema.keys()) {
    if (cfg.values_.count(key)) continue;
    if (spec.default_value)
      cfg.values_[key] = {*spec.default_value, false};
    else if (!spec.doc.empty() && spec.doc.rfind("(optional)", 0) == 0)
      continue;  // optional without default: absence is meaningful
    else
      throw InputError(fmt::format("{}: required key '{}' is missing; allowed: {} ({})", source,
                                   key, describe_range(spec), spec.doc));
  }
  return cfg;
}

const ConfigValue& Config::value(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) throw std::logic_error("config key not declared or not set: " + key);
  it->second.used = true;
  return it->second.value;
}

std::vector<std::string> Config::unused_given_keys() const {
  std::vector<std::string> keys;
  for (const auto& [key, entry] : values_)
    if (entry.given && !entry.used) keys.push_back(key);
  return keys;
}

bool Config::get_bool(const std::string& key) const {
  return std::get<bool>(value(key));
}
std::int64_t Config::get_int(const std::string& key) const {
  return std::get<std::int64_t>(value(key));
}
double Config::get_real(const std::string& key) const {
  return std::get<double>(value(key));
}
const std::string& Config::get_string(const std::string& key) const {
  return std::get<std::string>(value(key));
}
const std::vector<double>& Config::get_real_list(const std::string& key) const {
  return std::get<std::vector<double>>(value(key));
}

void Config::fail(const std::string& key, const std::string& reason) const {
  std::string shown = has(key) ? to_toml_text(value(key)) : "(unset)";
  throw InputError(fmt::format("{}: {} = {} {}", source_, key, shown, reason));
}

std::string Config::effective_toml() const {
  // Group dotted keys under their table headers for readability.
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> groups;
  for (const auto& [key, entry] : values_) {
    const ConfigValue& v = entry.value;
    auto dot = key.rfind('.');
    std::string table = dot == std::string::npos ? "" : key.substr(0, dot);
    std::string leaf = dot == std::string::npos ? key : key.substr(dot + 1);
    groups[table].emplace_back(leaf, to_toml_text(v));
  }
  std::string out;
  for (const auto& [table, kv] : groups) {
    if (!table.empty()) out += "\n[" + table + "]\n";
    for (const auto& [k, v] : kv) out += k + " = " + v + "\n";
  }
  return out;
}

}  // namespace biota::core
