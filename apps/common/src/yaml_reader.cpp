#include "sarloc/app/yaml_reader.hpp"

#include <regex>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace sarloc::app {
namespace {

std::string scalar_text(const YAML::Node& node) {
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  return "null";
}

}  // namespace

YamlReader YamlReader::from_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open config file");
  std::stringstream text;
  text << in.rdbuf();
  return from_string(text.str(), path);
}

YamlReader YamlReader::from_string(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(name + ": not valid YAML: " + e.what());
  }
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);  // an empty file means "defaults"
  if (!root.IsMap()) throw ConfigError(name + ": top level must be a map of sections");
  return YamlReader(root, "", name);
}

YamlReader::YamlReader(YAML::Node node, std::string path, std::string source)
    : node_(std::move(node)),
      path_(std::move(path)),
      source_(std::move(source)),
      consumed_(std::make_shared<std::set<std::string>>()) {}

namespace {
thread_local std::set<std::string>* key_recorder = nullptr;
thread_local std::map<std::string, YamlReader::ValueRecorder::Value>* value_recorder = nullptr;

// 17 digits read back to the same double: equal values show equal text, unequal ones differ.
std::string shown(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}
std::string shown(bool v) { return v ? "true" : "false"; }
template <class Int>
std::string shown(Int v) {
  return std::to_string(v);
}
std::string shown(const std::string& v) { return v; }
template <class T>
std::string shown_list(const T& values) {
  std::string out = "[";
  for (std::size_t i = 0; i < static_cast<std::size_t>(values.size()); ++i) out += (i ? ", " : "") + shown(values[i]);
  return out + "]";
}
}  // namespace

YamlReader::KeyRecorder::KeyRecorder() : previous_(key_recorder) { key_recorder = &keys_; }
YamlReader::KeyRecorder::~KeyRecorder() { key_recorder = previous_; }

YamlReader::ValueRecorder::ValueRecorder() : previous_(value_recorder) { value_recorder = &values_; }
YamlReader::ValueRecorder::~ValueRecorder() { value_recorder = previous_; }

void YamlReader::note(const std::string& key, const std::string& text) const {
  if (value_recorder == nullptr) return;
  auto& v = (*value_recorder)[key_path(key)];
  v.text = text;
  v.written = consumed_->count(key) != 0;
}

bool YamlReader::has(const std::string& key) const {
  if (key_recorder != nullptr) {
    // Every read(), require(), child() and child_list() asks here first.
    static const std::regex kIndex(R"(\[[0-9]+\])");
    key_recorder->insert(std::regex_replace(key_path(key), kIndex, "[]"));
  }
  return node_.IsMap() && node_[key] && !node_[key].IsNull();
}

std::string YamlReader::key_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void YamlReader::fail(const std::string& key, const std::string& rule) const {
  throw ConfigError(source_ + ": " + key_path(key) + " " + rule);
}

YAML::Node YamlReader::lookup(const std::string& key) {
  consumed_->insert(key);
  return node_[key];
}

template <>
void YamlReader::read<bool>(const std::string& key, bool& value) {
  if (!has(key)) return note(key, shown(value));
  const YAML::Node n = lookup(key);
  if (!n.IsScalar()) fail(key, "= " + scalar_text(n) + ": expected true or false");
  const std::string& s = n.Scalar();
  if (s == "true" || s == "True" || s == "yes") {
    value = true;
  } else if (s == "false" || s == "False" || s == "no") {
    value = false;
  } else {
    fail(key, "= " + scalar_text(n) + ": expected true or false");
  }
  note(key, shown(value));
}

namespace {

// Integer parsing that rejects fractions, overflow and trailing junk ("12abc").
template <class Int>
bool parse_integer(const std::string& text, Int& out) {
  if (text.empty()) return false;
  std::size_t used = 0;
  try {
    if constexpr (std::is_signed_v<Int>) {
      const long long v = std::stoll(text, &used, 0);
      if (v < std::numeric_limits<Int>::min() || v > std::numeric_limits<Int>::max()) return false;
      out = static_cast<Int>(v);
    } else {
      if (text.find('-') != std::string::npos) return false;
      const unsigned long long v = std::stoull(text, &used, 0);
      if (v > std::numeric_limits<Int>::max()) return false;
      out = static_cast<Int>(v);
    }
  } catch (const std::exception&) {
    return false;
  }
  return used == text.size();
}

}  // namespace

#define SARLOC_YAML_INTEGER(Type, what)                                            \
  template <>                                                                      \
  void YamlReader::read<Type>(const std::string& key, Type& value) {               \
    if (!has(key)) return note(key, shown(value));                                 \
    const YAML::Node n = lookup(key);                                              \
    Type parsed{};                                                                 \
    if (!n.IsScalar() || !parse_integer(n.Scalar(), parsed))                       \
      fail(key, "= " + scalar_text(n) + ": expected " what);                       \
    value = parsed;                                                                \
    note(key, shown(value));                                                       \
  }
SARLOC_YAML_INTEGER(int, "an integer")
SARLOC_YAML_INTEGER(unsigned, "a non-negative integer")
SARLOC_YAML_INTEGER(std::uint64_t, "a non-negative integer")
SARLOC_YAML_INTEGER(std::int64_t, "an integer")
#undef SARLOC_YAML_INTEGER

namespace {

bool parse_finite_double(const YAML::Node& n, double& out) {
  if (!n.IsScalar()) return false;
  const std::string& s = n.Scalar();
  std::size_t used = 0;
  try {
    out = std::stod(s, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == s.size() && std::isfinite(out);
}

}  // namespace

template <>
void YamlReader::read<double>(const std::string& key, double& value) {
  if (!has(key)) return note(key, shown(value));
  const YAML::Node n = lookup(key);
  double parsed = 0.0;
  if (!parse_finite_double(n, parsed)) fail(key, "= " + scalar_text(n) + ": expected a finite number");
  value = parsed;
  note(key, shown(value));
}

template <>
void YamlReader::read<std::string>(const std::string& key, std::string& value) {
  if (!has(key)) return note(key, value);
  const YAML::Node n = lookup(key);
  if (!n.IsScalar()) fail(key, "= " + scalar_text(n) + ": expected a string");
  value = n.Scalar();
  note(key, value);
}

template <>
void YamlReader::read<std::vector<double>>(const std::string& key, std::vector<double>& value) {
  if (!has(key)) return note(key, shown_list(value));
  const YAML::Node n = lookup(key);
  if (!n.IsSequence()) fail(key, "= " + scalar_text(n) + ": expected a list of numbers");
  std::vector<double> parsed;
  for (std::size_t i = 0; i < n.size(); ++i) {
    double v = 0.0;
    if (!parse_finite_double(n[i], v)) {
      fail(key + "[" + std::to_string(i) + "]", "= " + scalar_text(n[i]) + ": expected a finite number");
    }
    parsed.push_back(v);
  }
  value = std::move(parsed);
  note(key, shown_list(value));
}

template <>
void YamlReader::read<std::vector<std::string>>(const std::string& key, std::vector<std::string>& value) {
  if (!has(key)) return note(key, shown_list(value));
  const YAML::Node n = lookup(key);
  if (!n.IsSequence()) fail(key, "= " + scalar_text(n) + ": expected a list of strings");
  std::vector<std::string> parsed;
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (!n[i].IsScalar()) fail(key + "[" + std::to_string(i) + "]", "= " + scalar_text(n[i]) + ": expected a string");
    parsed.push_back(n[i].Scalar());
  }
  value = std::move(parsed);
  note(key, shown_list(value));
}

template <>
void YamlReader::read<Eigen::Vector3d>(const std::string& key, Eigen::Vector3d& value) {
  std::vector<double> v;
  if (!has(key)) return note(key, shown_list(value));
  read(key, v);
  if (v.size() != 3) fail(key, "has " + std::to_string(v.size()) + " numbers: expected [x, y, z]");
  value = Eigen::Vector3d(v[0], v[1], v[2]);
  note(key, shown_list(value));
}

YamlReader YamlReader::child(const std::string& key) {
  if (!has(key)) return YamlReader(YAML::Node(YAML::NodeType::Map), key_path(key), source_);
  const YAML::Node n = lookup(key);
  if (!n.IsMap()) fail(key, "= " + scalar_text(n) + ": expected a map");
  return YamlReader(n, key_path(key), source_);
}

std::vector<YamlReader> YamlReader::child_list(const std::string& key) {
  std::vector<YamlReader> out;
  if (!has(key)) return out;
  const YAML::Node n = lookup(key);
  if (!n.IsSequence()) fail(key, "= " + scalar_text(n) + ": expected a list");
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string item = key_path(key) + "[" + std::to_string(i) + "]";
    if (!n[i].IsMap()) throw ConfigError(source_ + ": " + item + " = " + scalar_text(n[i]) + ": expected a map");
    out.emplace_back(n[i], item, source_);
  }
  return out;
}

void YamlReader::expect_done() const {
  if (!node_.IsMap()) return;
  std::string unknown;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (consumed_->count(key) == 0) unknown += (unknown.empty() ? "" : ", ") + key_path(key);
  }
  if (!unknown.empty()) throw ConfigError(source_ + ": unknown key(s): " + unknown);
}

}  // namespace sarloc::app
