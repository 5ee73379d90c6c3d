// A parameter namespace as a value: its tree (XmlRpc, what ROS parameters are) and its name for
// messages. It comes from the parameter server (Params::of) in a node, or straight from the
// robot's YAML (Params::fromYamlFile) in a benchmark or a unit test, with no master: both read a
// robot's values through the same config reader, so neither copies them by hand.
// The same strict rules as parameters.h (which uses the same conversions): a missing required or
// mistyped value throws ParameterError naming the parameter; integers are accepted as numbers.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

#include "robot_core/parameter_error.h"

namespace ros {
class NodeHandle;
}

namespace robot_core {

class Params {
 public:
  Params() = default;
  Params(XmlRpc::XmlRpcValue tree, std::string ns);

  // Everything under a node handle's namespace (one request to the master).
  static Params of(const ros::NodeHandle& nh);
  // The block at `path` ("hal/driver") of a YAML file loaded as `rosparam load` would, named
  // "/hal/driver" in messages. Throws ParameterError when the file or the block is missing.
  static Params fromYamlFile(const std::string& file, const std::string& path = "");

  // A sub-namespace ("limits"); empty (every optional value at its default) when absent.
  Params operator[](const std::string& name) const;
  // The same, refusing a value that is present but not a dictionary.
  Params block(const std::string& name) const;
  // The names of the dictionaries under a dictionary `name` (motors: {left: {..}, right: {..}}),
  // in key order; none when absent.
  std::vector<std::string> blockNames(const std::string& name) const;
  // Every key of this dictionary, whatever its value (none when this is not a dictionary).
  std::vector<std::string> keys() const;
  // The dictionaries of a list `name` (zones: [{..}, {..}]), named "<name>[i]"; none when absent.
  std::vector<Params> items(const std::string& name) const;
  const std::string& ns() const { return ns_; }
  std::string qualified(const std::string& name) const;
  bool has(const std::string& name) const;

  double requireDouble(const std::string& name) const;
  int requireInt(const std::string& name) const;
  std::string requireString(const std::string& name) const;
  double optionalDouble(const std::string& name, double fallback) const;
  int optionalInt(const std::string& name, int fallback) const;
  bool optionalBool(const std::string& name, bool fallback) const;
  std::string optionalString(const std::string& name, const std::string& fallback) const;
  // A list of numbers, empty when absent; its length must be in [min_size, max_size].
  std::vector<double> optionalDoubleList(const std::string& name, std::size_t min_size = 0,
                                         std::size_t max_size = static_cast<std::size_t>(-1)) const;
  // A list of lists of `width` numbers each ([[x, y], ..] for width 2), empty when absent.
  std::vector<std::vector<double>> optionalDoubleRows(const std::string& name, std::size_t width) const;
  std::vector<std::string> optionalStringList(const std::string& name) const;

  void requirePositive(const std::string& name, double value) const;
  void requireInRange(const std::string& name, double value, double lo, double hi) const;
  void requireOneOf(const std::string& name, const std::string& value, const std::vector<std::string>& allowed) const;
  // Throws ParameterError("parameter <ns>/<name>: <reason>") unless `reason` is empty (a config
  // struct's invalidReason()).
  void check(const std::string& name, const std::string& reason) const;

 private:
  XmlRpc::XmlRpcValue* find(const std::string& name) const;  // null when absent

  mutable XmlRpc::XmlRpcValue tree_;  // XmlRpcValue's lookups and conversions are not const
  std::string ns_;
};

}  // namespace robot_core
