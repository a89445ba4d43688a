#pragma once
/// \file config.hpp
/// \brief Schema-checked TOML decks: every key is declared with type, default, range, unit and doc.
///
/// Modules declare their keys on a `ConfigSchema`; a `Config` is a deck validated against it.
/// Unknown keys, wrong types, missing required keys and out-of-range values throw `InputError`
/// with one line naming file, key, value and the allowed range (AMReX ParmParse style, but strict).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace biota::core {

/// \brief A configuration value: bool, integer, real, string, or list of reals.
using ConfigValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

/// \brief Kind of a declared key.
enum class ConfigType { kBool, kInt, kReal, kString, kRealList };

/// \brief Declaration of one key.
struct KeySpec {
  ConfigType type = ConfigType::kReal;
  std::optional<ConfigValue> default_value;  ///< absent: the key is required
  std::optional<double> min, max;            ///< numeric bounds (inclusive unless *_exclusive)
  bool min_exclusive = false, max_exclusive = false;
  std::vector<std::string> choices;  ///< allowed strings (empty: any)
  int list_length = -1;              ///< required list length (-1: any)
  std::string unit;                  ///< physical unit, "-" for dimensionless
  std::string doc;                   ///< one-line description
};

/// \brief The set of keys a run accepts; filled by each module's `declare_config`.
class ConfigSchema {
 public:
  /// \brief Declare a key; declaring the same key twice with a different spec is a programming
  /// error.
  /// \throws std::logic_error for an integer key without both bounds: every integer ends in a
  /// C++ integer of fixed width (an interval of 2^32 became 0 and a division by zero), so each
  /// one states the largest value its code can take.
  void add(const std::string& key, KeySpec spec);
  // Convenience declarations.
  void add_real(const std::string& key, std::optional<double> def, std::optional<double> min,
                std::optional<double> max, std::string unit, std::string doc,
                bool min_exclusive = false);
  /// \brief An integer key with its inclusive range [min, max] (both required).
  void add_int(const std::string& key, std::optional<std::int64_t> def, std::int64_t min,
               std::int64_t max, std::string doc);
  void add_bool(const std::string& key, bool def, std::string doc);
  void add_string(const std::string& key, std::optional<std::string> def,
                  std::vector<std::string> choices, std::string doc);
  void add_real_list(const std::string& key, std::optional<std::vector<double>> def, int length,
                     std::string unit, std::string doc);

  const std::map<std::string, KeySpec>& keys() const { return keys_; }
  const KeySpec* find(const std::string& key) const;
  /// \brief Markdown table of every key (the deck reference in docs/ is generated from this).
  std::string reference_markdown() const;

 private:
  std::map<std::string, KeySpec> keys_;
};

/// \brief Human-readable allowed range of a key, e.g. "(0.5, 2]" or "one of {bgk, trt}".
std::string describe_range(const KeySpec& spec);
/// \brief Render a value as TOML text.
std::string to_toml_text(const ConfigValue& v);
/// \brief The text of an input file. \throws InputError "<path>: is a directory, not <noun>" (an
/// ifstream opens a directory and reads it as empty, which the parsers reported as a missing
/// key or line) or "<path>: <unreadable>" for a missing or unreadable file.
std::string read_input_file(const std::string& path, const std::string& noun,
                            const std::string& unreadable);
/// \brief The text of a deck file (read_input_file with the deck's wording).
std::string read_deck_text(const std::string& file);
/// \brief The string a `--set key=value` gives a string key: TOML ("flock", 'flock') or bare.
std::string override_string_value(const std::string& value);

/// \brief A deck validated against a schema; holds the effective value of every declared key
/// that has a value (given or default).
class Config {
 public:
  /// \brief Parse and validate `file`, then apply `overrides` ("key=value" strings).
  static Config from_file(const ConfigSchema& schema, const std::string& file,
                          const std::vector<std::string>& overrides = {});
  /// \brief Parse and validate TOML text (`source_name` is used in messages).
  static Config from_string(const ConfigSchema& schema, const std::string& toml_text,
                            const std::string& source_name,
                            const std::vector<std::string>& overrides = {});

  /// \brief Whether the key has a value; counts as a use of it (see unused_given_keys).
  bool has(const std::string& key) const {
    auto it = values_.find(key);
    return it != values_.end() && (it->second.used = true);
  }
  bool get_bool(const std::string& key) const;
  std::int64_t get_int(const std::string& key) const;
  double get_real(const std::string& key) const;
  const std::string& get_string(const std::string& key) const;
  const std::vector<double>& get_real_list(const std::string& key) const;
  /// \brief Throw an InputError naming this deck, `key` and `value` with the reason.
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const;

  /// \brief Effective configuration as TOML text (defaults included); printed and stored in output.
  std::string effective_toml() const;
  const std::string& source() const { return source_; }
  const ConfigSchema& schema() const { return *schema_; }
  /// \brief Keys the deck or `--set` gave that nothing has read yet (has() or get_*()): keys of
  /// another mode of the scenario (a moving-wall velocity on a face that is not a moving wall,
  /// the general growth model's tables under the Ulva model), which a run ignores.
  std::vector<std::string> unused_given_keys() const;

 private:
  const ConfigSchema* schema_ = nullptr;
  std::string source_;
  struct Entry {
    ConfigValue value;
    bool given = false;         ///< by the deck or --set (not a default)
    mutable bool used = false;  ///< read by has() or get_*()
  };
  std::map<std::string, Entry> values_;
  const ConfigValue& value(const std::string& key) const;
};

}  // namespace biota::core
