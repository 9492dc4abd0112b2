#pragma once
// Strict YAML reading for config structs: every key is type-checked, unknown keys are errors,
// and every message names the key path and the offending value.
//
//   auto yaml = YamlReader::from_file("mission.yaml");
//   auto sog = yaml.child("sog");
//   sog.read("initial_components", config.initial_components);  // absent: keeps the default
//   sog.expect_done();  // "sog.initial_componets: unknown key"
//   yaml.expect_done();
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::app {

class YamlReader {
 public:
  static YamlReader from_file(const std::string& path);
  static YamlReader from_string(const std::string& text, const std::string& name);

  /// A reader over an already parsed node; `path` prefixes every message ("sog").
  YamlReader(YAML::Node node, std::string path, std::string source);

  bool has(const std::string& key) const;

  /// Reads `key` into `value` when present; leaves `value` (the default) when absent.
  template <class T>
  void read(const std::string& key, T& value);

  /// Like read() but a missing key is an error.
  template <class T>
  void require(const std::string& key, T& value);

  /// The map under `key` (an empty map when absent).
  YamlReader child(const std::string& key);

  /// The maps of the sequence under `key` (empty when absent).
  std::vector<YamlReader> child_list(const std::string& key);

  /// Throws ConfigError naming every key that nobody read.
  void expect_done() const;

  /// While one is alive, every key a YamlReader on this thread asks for (present or not) is
  /// recorded with its full path, list indices written "[]" ("rescuers[].id"): the keys a
  /// loader accepts, so that a test can hold docs/configuration.md to them.
  class KeyRecorder {
   public:
    KeyRecorder();
    ~KeyRecorder();
    KeyRecorder(const KeyRecorder&) = delete;
    KeyRecorder& operator=(const KeyRecorder&) = delete;
    const std::set<std::string>& keys() const { return keys_; }

   private:
    std::set<std::string> keys_;
    std::set<std::string>* previous_;
  };

  /// While one is alive, every read() on this thread records the value its key holds after
  /// the read (the file's, or the default it left) with its full path, and whether the file
  /// wrote it. Reading an empty document with one alive lists a config struct's values
  /// without changing them: how config_consistency_test compares what each program runs.
  class ValueRecorder {
   public:
    struct Value {
      std::string text;      ///< the value as read() left it ("0.05", "true", "[1, 2, 3]", "realistic")
      bool written = false;  ///< the file wrote this key
    };
    ValueRecorder();
    ~ValueRecorder();
    ValueRecorder(const ValueRecorder&) = delete;
    ValueRecorder& operator=(const ValueRecorder&) = delete;
    const std::map<std::string, Value>& values() const { return values_; }

   private:
    std::map<std::string, Value> values_;
    std::map<std::string, Value>* previous_;
  };

  const std::string& path() const { return path_; }
  const std::string& source() const { return source_; }
  const YAML::Node& node() const { return node_; }

 private:
  std::string key_path(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& rule) const;
  YAML::Node lookup(const std::string& key);
  /// Hands `value` to the ValueRecorder alive on this thread, if any.
  void note(const std::string& key, const std::string& text) const;

  YAML::Node node_;
  std::string path_;
  std::string source_;
  std::shared_ptr<std::set<std::string>> consumed_;
};

// Conversions supported by read()/require(); defined in yaml_reader.cpp.
template <> void YamlReader::read<bool>(const std::string&, bool&);
template <> void YamlReader::read<int>(const std::string&, int&);
template <> void YamlReader::read<unsigned>(const std::string&, unsigned&);
template <> void YamlReader::read<std::uint64_t>(const std::string&, std::uint64_t&);
template <> void YamlReader::read<std::int64_t>(const std::string&, std::int64_t&);
template <> void YamlReader::read<double>(const std::string&, double&);
template <> void YamlReader::read<std::string>(const std::string&, std::string&);
template <> void YamlReader::read<std::vector<double>>(const std::string&, std::vector<double>&);
template <> void YamlReader::read<std::vector<std::string>>(const std::string&, std::vector<std::string>&);
template <> void YamlReader::read<Eigen::Vector3d>(const std::string&, Eigen::Vector3d&);

template <class T>
void YamlReader::require(const std::string& key, T& value) {
  if (!has(key)) fail(key, "is required");
  read(key, value);
}

}  // namespace sarloc::app
