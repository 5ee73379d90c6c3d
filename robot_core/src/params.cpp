#include "robot_core/params.h"

#include <ros/console.h>
#include <ros/node_handle.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <regex>
#include <sstream>

#include "parameter_rules.h"

namespace robot_core {

namespace {

// A number as a config writes it: 0.05, 2, 1e+06.
std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  std::ostringstream s;
  s << v;
  return s.str();
}

// "3 ", "2..4 ", "" (any length): a list's length as its type says it.
std::string count(std::size_t min_size, std::size_t max_size) {
  if (max_size == static_cast<std::size_t>(-1)) return min_size ? std::to_string(min_size) + " or more " : "";
  if (min_size == max_size) return std::to_string(min_size) + " ";
  return std::to_string(min_size) + ".." + std::to_string(max_size) + " ";
}

// A plain YAML scalar typed as `rosparam load` types it (PyYAML, YAML 1.1): bool, int (decimal,
// 0x hex, 0o or leading-0 octal), float (with .inf / .nan), else string. Quoted: always a string.
XmlRpc::XmlRpcValue scalarOf(const YAML::Node& n) {
  const std::string s = n.Scalar();
  if (n.Tag() == "!") return XmlRpc::XmlRpcValue(s);  // quoted
  std::string l = s;
  std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::tolower(c); });
  if (l == "true" || l == "yes" || l == "on") return XmlRpc::XmlRpcValue(true);
  if (l == "false" || l == "no" || l == "off") return XmlRpc::XmlRpcValue(false);
  static const std::regex decimal("[-+]?(0|[1-9][0-9_]*)"), hex("[-+]?0x[0-9a-fA-F_]+"), octal("[-+]?0o?[0-7_]+");
  std::string digits = s;
  digits.erase(std::remove(digits.begin(), digits.end(), '_'), digits.end());
  if (std::regex_match(s, decimal)) return XmlRpc::XmlRpcValue(static_cast<int>(std::stol(digits, nullptr, 10)));
  if (std::regex_match(s, hex)) return XmlRpc::XmlRpcValue(static_cast<int>(std::stol(digits, nullptr, 16)));
  if (std::regex_match(s, octal)) {
    std::string o = digits;
    const auto pos = o.find("0o");
    if (pos != std::string::npos) o.erase(pos, 2);
    return XmlRpc::XmlRpcValue(static_cast<int>(std::stol(o, nullptr, 8)));
  }
  if (l == ".inf" || l == "+.inf") return XmlRpc::XmlRpcValue(INFINITY);
  if (l == "-.inf") return XmlRpc::XmlRpcValue(-INFINITY);
  if (l == ".nan") return XmlRpc::XmlRpcValue(NAN);
  // YAML 1.1 needs the dot: 1e-3 is a string there (and so in rosparam), 1.0e-3 a number
  static const std::regex real("[-+]?([0-9][0-9_]*)?\\.[0-9_]*([eE][-+][0-9]+)?");
  if (std::regex_match(s, real) && s.find_first_of("0123456789") != std::string::npos)
    return XmlRpc::XmlRpcValue(std::stod(digits));
  return XmlRpc::XmlRpcValue(s);
}

XmlRpc::XmlRpcValue treeOf(const YAML::Node& n) {
  XmlRpc::XmlRpcValue v;
  switch (n.Type()) {
    case YAML::NodeType::Map:
      for (const auto& kv : n) v[kv.first.as<std::string>()] = treeOf(kv.second);
      break;
    case YAML::NodeType::Sequence:
      v.setSize(static_cast<int>(n.size()));
      for (std::size_t i = 0; i < n.size(); ++i) v[static_cast<int>(i)] = treeOf(n[i]);
      break;
    case YAML::NodeType::Scalar:
      v = scalarOf(n);
      break;
    default:  // null: left invalid, as if absent
      break;
  }
  return v;
}

std::vector<std::string> split(const std::string& path) {
  std::vector<std::string> parts;
  std::stringstream s(path);
  std::string p;
  while (std::getline(s, p, '/'))
    if (!p.empty()) parts.push_back(p);
  return parts;
}

}  // namespace

Params::Params(XmlRpc::XmlRpcValue tree, std::string ns) : tree_(std::move(tree)), ns_(std::move(ns)) {}

Params Params::of(const ros::NodeHandle& nh) {
  XmlRpc::XmlRpcValue tree;
  nh.getParam(nh.getNamespace(), tree);  // nothing set: an empty namespace, every default
  return Params(tree, nh.getNamespace());
}

Params Params::fromYamlFile(const std::string& file, const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::Exception& e) {
    throw ParameterError("cannot read " + file + ": " + e.what());
  }
  Params all(treeOf(root), "");
  if (path.empty()) return all;
  if (!all.has(path)) throw ParameterError(file + " has no block " + path);
  return all[path];
}

Params Params::child(XmlRpc::XmlRpcValue tree, std::string ns) const {
  Params p(std::move(tree), std::move(ns));
  p.asked_ = asked_;
  return p;
}

XmlRpc::XmlRpcValue* Params::find(const std::string& name) const {
  if (asked_) {  // null only in a moved-from Params
    std::lock_guard<std::mutex> lock(asked_->mutex);
    asked_->names.insert(qualified(name));
  }
  XmlRpc::XmlRpcValue* v = &tree_;
  for (const auto& part : split(name)) {
    if (v->getType() != XmlRpc::XmlRpcValue::TypeStruct || !v->hasMember(part)) return nullptr;
    v = &(*v)[part];
  }
  return v->valid() ? v : nullptr;
}

Params Params::operator[](const std::string& name) const {
  const XmlRpc::XmlRpcValue* v = find(name);
  return child(v ? *v : XmlRpc::XmlRpcValue(), qualified(name));
}

Params Params::block(const std::string& name) const {
  const XmlRpc::XmlRpcValue* v = find(name);
  if (v && v->getType() != XmlRpc::XmlRpcValue::TypeStruct) check(name, "must be a dictionary");
  return child(v ? *v : XmlRpc::XmlRpcValue(), qualified(name));
}

std::vector<std::string> Params::blockNames(const std::string& name) const {
  {
    std::lock_guard<std::mutex> lock(asked_->mutex);
    asked_->block_maps.insert(qualified(name));
  }
  declare(name, "dictionary of named blocks", false, "{}");
  std::vector<std::string> out;
  XmlRpc::XmlRpcValue* v = find(name);
  if (!v) return out;
  if (v->getType() != XmlRpc::XmlRpcValue::TypeStruct) check(name, "must be a dictionary of named blocks");
  for (auto& e : *v) {
    if (e.second.getType() != XmlRpc::XmlRpcValue::TypeStruct) check(name + "/" + e.first, "must be a dictionary");
    out.push_back(e.first);
  }
  return out;
}

std::vector<std::string> Params::requireBlockNames(const std::string& name) const {
  if (!has(name)) rules::missing(qualified(name), "a dictionary of named blocks");
  std::vector<std::string> out = blockNames(name);
  declare(name, "dictionary of named blocks", true, "");
  if (out.empty()) check(name, "must name at least one block");
  return out;
}

std::vector<std::string> Params::keys() const {
  std::vector<std::string> out;
  if (tree_.getType() != XmlRpc::XmlRpcValue::TypeStruct) return out;
  std::lock_guard<std::mutex> lock(asked_->mutex);
  for (auto& e : tree_) {
    out.push_back(e.first);
    asked_->names.insert(qualified(e.first));
  }
  return out;
}

std::vector<Params> Params::items(const std::string& name) const {
  declare(name, "list of dictionaries", false, "[]");
  std::vector<Params> out;
  XmlRpc::XmlRpcValue* v = find(name);
  if (!v) return out;
  if (v->getType() != XmlRpc::XmlRpcValue::TypeArray) check(name, "must be a list");
  for (int i = 0; i < v->size(); ++i) {
    const std::string item = qualified(name) + "[" + std::to_string(i) + "]";
    if ((*v)[i].getType() != XmlRpc::XmlRpcValue::TypeStruct)
      throw ParameterError("parameter " + item + ": must be a dictionary");
    out.push_back(child((*v)[i], item));
  }
  return out;
}

std::string Params::qualified(const std::string& name) const { return ns_ + "/" + name; }

bool Params::has(const std::string& name) const { return find(name) != nullptr; }

double Params::requireDouble(const std::string& name) const {
  declare(name, "number", true, "");
  XmlRpc::XmlRpcValue* v = find(name);
  if (!v) rules::missing(qualified(name), "a number");
  return rules::toNumber(*v, qualified(name));
}

int Params::requireInt(const std::string& name) const {
  declare(name, "integer", true, "");
  XmlRpc::XmlRpcValue* v = find(name);
  if (!v) rules::missing(qualified(name), "an integer");
  return rules::toInt(*v, qualified(name));
}

std::string Params::requireString(const std::string& name) const {
  declare(name, "string", true, "");
  XmlRpc::XmlRpcValue* v = find(name);
  if (!v) rules::missing(qualified(name), "a string");
  return rules::toString(*v, qualified(name));
}

double Params::optionalDouble(const std::string& name, double fallback) const {
  return optionalDouble(name, fallback, number(fallback));
}

double Params::optionalDouble(const std::string& name, double fallback, const std::string& fallback_named) const {
  declare(name, "number", false, fallback_named);
  XmlRpc::XmlRpcValue* v = find(name);
  return v ? rules::toNumber(*v, qualified(name)) : fallback;
}

int Params::optionalInt(const std::string& name, int fallback) const {
  declare(name, "integer", false, std::to_string(fallback));
  XmlRpc::XmlRpcValue* v = find(name);
  return v ? rules::toInt(*v, qualified(name)) : fallback;
}

bool Params::optionalBool(const std::string& name, bool fallback) const {
  declare(name, "boolean", false, fallback ? "true" : "false");
  XmlRpc::XmlRpcValue* v = find(name);
  return v ? rules::toBool(*v, qualified(name)) : fallback;
}

std::string Params::optionalString(const std::string& name, const std::string& fallback) const {
  declare(name, "string", false, "'" + fallback + "'");
  XmlRpc::XmlRpcValue* v = find(name);
  return v ? rules::toString(*v, qualified(name)) : fallback;
}

std::vector<double> Params::optionalDoubleList(const std::string& name, std::size_t min_size,
                                               std::size_t max_size) const {
  declare(name, "list of " + count(min_size, max_size) + "numbers", false, "[]");
  std::vector<double> out;
  XmlRpc::XmlRpcValue* v = find(name);
  if (!v) return out;
  if (v->getType() != XmlRpc::XmlRpcValue::TypeArray) check(name, "must be a list of numbers");
  for (int i = 0; i < v->size(); ++i) out.push_back(rules::toNumber((*v)[i], qualified(name) + "[" + std::to_string(i) + "]"));
  if (out.size() < min_size || out.size() > max_size) {
    const std::string n = std::to_string(min_size) +
                          (min_size == max_size ? "" : max_size == static_cast<std::size_t>(-1) ? " or more"
                                                                                               : ".." + std::to_string(max_size));
    check(name, "must have " + n + " numbers");
  }
  return out;
}

std::vector<std::vector<double>> Params::optionalDoubleRows(const std::string& name, std::size_t width) const {
  declare(name, "list of [" + std::string(width == 2 ? "x, y" : std::to_string(width) + " numbers") + "]", false, "[]");
  std::vector<std::vector<double>> out;
  XmlRpc::XmlRpcValue* v = find(name);
  if (!v) return out;
  const std::string form = "must be a list of [" + std::string(width == 2 ? "x, y" : std::to_string(width) + " numbers") + "]";
  if (v->getType() != XmlRpc::XmlRpcValue::TypeArray) check(name, form);
  for (int i = 0; i < v->size(); ++i) {
    XmlRpc::XmlRpcValue& row = (*v)[i];
    if (row.getType() != XmlRpc::XmlRpcValue::TypeArray || row.size() != static_cast<int>(width)) check(name, form);
    std::vector<double> r;
    for (int k = 0; k < row.size(); ++k) r.push_back(rules::toNumber(row[k], qualified(name) + "[" + std::to_string(i) + "]"));
    out.push_back(r);
  }
  return out;
}

std::vector<std::string> Params::optionalStringList(const std::string& name,
                                                  const std::vector<std::string>& fallback) const {
  std::string shown;
  for (const auto& f : fallback) shown += (shown.empty() ? "" : ", ") + f;
  declare(name, "list of strings", false, "[" + shown + "]");
  std::vector<std::string> out;
  XmlRpc::XmlRpcValue* v = find(name);
  if (!v) return fallback;
  if (v->getType() != XmlRpc::XmlRpcValue::TypeArray) check(name, "must be a list of strings");
  for (int i = 0; i < v->size(); ++i) out.push_back(rules::toString((*v)[i], qualified(name) + "[" + std::to_string(i) + "]"));
  return out;
}

std::vector<std::pair<std::string, int>> Params::optionalIntMap(const std::string& name) const {
  declare(name, "dictionary of name: integer", false, "{}");
  std::vector<std::pair<std::string, int>> out;
  XmlRpc::XmlRpcValue* v = find(name);
  if (!v) return out;
  const std::string form = "must be a dictionary of name: index (integers >= 0)";
  if (v->getType() != XmlRpc::XmlRpcValue::TypeStruct) check(name, form);
  for (auto& e : *v) {
    const int index = rules::toInt(e.second, qualified(name + "/" + e.first));
    if (index < 0)
      throw ParameterError("parameter " + qualified(name + "/" + e.first) + " = " + std::to_string(index) + ": " + form);
    out.emplace_back(e.first, index);
  }
  std::lock_guard<std::mutex> lock(asked_->mutex);
  for (const auto& e : out) asked_->names.insert(qualified(name + "/" + e.first));
  return out;
}

void Params::requirePositive(const std::string& name, double value) const {
  declareRule(name, "> 0");
  rules::positive(qualified(name), value);
}

void Params::requireInRange(const std::string& name, double value, double lo, double hi) const {
  declareRule(name, std::isinf(hi) ? ">= " + number(lo) : std::isinf(lo) ? "<= " + number(hi)
                                                                         : number(lo) + " .. " + number(hi));
  rules::inRange(qualified(name), value, lo, hi);
}

void Params::requireOneOf(const std::string& name, const std::string& value,
                          const std::vector<std::string>& allowed) const {
  std::string shown;
  for (const auto& a : allowed) shown += (shown.empty() ? "" : ", ") + (a.empty() ? std::string("''") : a);
  declareRule(name, "one of: " + shown);
  rules::oneOf(qualified(name), value, allowed);
}

void Params::declare(const std::string& name, const std::string& type, bool required,
                     const std::string& fallback) const {
  if (!asked_) return;
  std::lock_guard<std::mutex> lock(asked_->mutex);
  ParameterDeclaration& d = asked_->declared[qualified(name)];  // keeps a meaning described first
  d.type = type;
  d.required = required;
  d.fallback = fallback;
}

void Params::describe(const std::string& name, const std::string& meaning) const {
  if (!asked_) return;
  std::lock_guard<std::mutex> lock(asked_->mutex);
  asked_->declared[qualified(name)].meaning = meaning;
}

void Params::declareRule(const std::string& name, const std::string& rule) const {
  if (!asked_) return;
  std::lock_guard<std::mutex> lock(asked_->mutex);
  asked_->declared[qualified(name)].rule = rule;
}

std::map<std::string, ParameterDeclaration> Params::declarations() const {
  std::map<std::string, ParameterDeclaration> out;
  const std::string prefix = ns_ + "/";
  static const std::regex item_index("\\[[0-9]+\\]");
  std::lock_guard<std::mutex> lock(asked_->mutex);
  for (const auto& [name, declaration] : asked_->declared) {
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    std::string general = name;
    // an entry of a dictionary of named blocks: its name is the config's, the table says <name>
    for (const auto& map : asked_->block_maps) {
      if (general.compare(0, map.size() + 1, map + "/") != 0) continue;
      const std::size_t end = general.find('/', map.size() + 1);
      if (end == std::string::npos) continue;
      general = map + "/<name>" + general.substr(end);
    }
    general = std::regex_replace(general, item_index, "[]");
    ParameterDeclaration& d = out[general.substr(prefix.size())];
    const std::string meaning = d.meaning.empty() ? declaration.meaning : d.meaning;
    if (d.type.empty()) d = declaration;
    d.meaning = meaning;
  }
  return out;
}

void Params::check(const std::string& name, const std::string& reason) const {
  if (!reason.empty()) throw ParameterError("parameter " + (name.empty() ? ns_ : qualified(name)) + ": " + reason);
}

std::string Params::renamed(const std::string& now, const std::string& old) const {
  if (has(now) || !has(old)) return now;
  ROS_WARN("%s is now called %s: rename it in the config", qualified(old).c_str(), qualified(now).c_str());
  return old;
}

void Params::unused(const std::string& name) const {
  std::lock_guard<std::mutex> lock(asked_->mutex);
  asked_->unused.insert(qualified(name));
}

void Params::collectUnasked(XmlRpc::XmlRpcValue& v, const std::string& path, std::vector<std::string>& out) const {
  if (asked_->unused.count(path)) return;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeStruct) {
    for (auto& e : v) collectUnasked(e.second, path + "/" + e.first, out);
    return;
  }
  const bool asked = asked_->names.count(path) > 0;
  if (asked && v.getType() == XmlRpc::XmlRpcValue::TypeArray) {
    // a list of dictionaries is read item by item (items()): each item's keys count
    bool dictionaries = v.size() > 0;
    for (int i = 0; i < v.size(); ++i) dictionaries = dictionaries && v[i].getType() == XmlRpc::XmlRpcValue::TypeStruct;
    if (dictionaries)
      for (int i = 0; i < v.size(); ++i) collectUnasked(v[i], path + "[" + std::to_string(i) + "]", out);
    return;
  }
  if (!asked) out.push_back(path + " = " + rules::quote(v));
}

std::vector<std::string> Params::unasked() const {
  std::vector<std::string> out;
  std::lock_guard<std::mutex> lock(asked_->mutex);
  if (tree_.getType() == XmlRpc::XmlRpcValue::TypeStruct) collectUnasked(tree_, ns_, out);
  return out;
}

std::vector<std::string> Params::askedKeys() const {
  std::set<std::string> keys;
  const std::string prefix = ns_ + "/";
  std::lock_guard<std::mutex> lock(asked_->mutex);
  for (const auto& name : asked_->names) {
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = name.substr(prefix.size());
    keys.insert(rest.substr(0, rest.find_first_of("/[")));
  }
  return std::vector<std::string>(keys.begin(), keys.end());
}

}  // namespace robot_core
