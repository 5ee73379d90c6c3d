// The one way the product reads parameters: a namespace as a value, its tree (XmlRpc, what ROS
// parameters are) and its name for messages. It comes from the parameter server (Params::of) in a
// node, or straight from the robot's YAML (Params::fromYamlFile) with no master: check_config, a
// benchmark or a unit test run a board's, a device's or the simulator's own reader over the
// config, so nothing copies a robot's values by hand.
// Strict: a missing required or mistyped value throws ParameterError, one line naming the
// parameter and quoting the value; integers are accepted as numbers; never a silent default.
// Every name a reader asks for is remembered (shared by the sub-namespaces): after a reader ran,
// unasked() lists the values in the tree it never looked at, the misspelt or unknown keys, and
// declarations() what it declared of each (type, default, allowed range): the generated
// parameter tables (make docs) come from the readers themselves.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "robot_core/parameter_error.h"

namespace ros {
class NodeHandle;
}

namespace robot_core {

// What a reader declared of one parameter by the way it read it.
struct ParameterDeclaration {
  std::string type;      // "number", "integer", "boolean", "string", "list of numbers", ...
  bool required = false;
  std::string fallback;  // the default, as the config would write it (optional values)
  std::string rule;      // what is allowed beyond the type: "> 0", "0 .. 10", "one of: a, b"
  std::string meaning;   // what it is, in a line (describe())
};

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
  // The same, required and not empty.
  std::vector<std::string> requireBlockNames(const std::string& name) const;
  // Every key of this dictionary, whatever its value (none when this is not a dictionary). A
  // reader that takes every key as it comes (a name -> value map) counts as asking for each.
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
  // The same, for a fallback taken from elsewhere: declared with `fallback_named` as its default
  // ("/robot/track_width"), not with a number.
  double optionalDouble(const std::string& name, double fallback, const std::string& fallback_named) const;
  int optionalInt(const std::string& name, int fallback) const;
  bool optionalBool(const std::string& name, bool fallback) const;
  std::string optionalString(const std::string& name, const std::string& fallback) const;
  // A list of numbers, empty when absent; its length must be in [min_size, max_size].
  std::vector<double> optionalDoubleList(const std::string& name, std::size_t min_size = 0,
                                         std::size_t max_size = static_cast<std::size_t>(-1)) const;
  // A list of lists of `width` numbers each ([[x, y], ..] for width 2), empty when absent.
  std::vector<std::vector<double>> optionalDoubleRows(const std::string& name, std::size_t width) const;
  std::vector<std::string> optionalStringList(const std::string& name,
                                              const std::vector<std::string>& fallback = {}) const;
  // A dictionary of name: integer >= 0 (joystick axes: {left_x: 0, ..}), in key order; none when absent.
  std::vector<std::pair<std::string, int>> optionalIntMap(const std::string& name) const;

  void requirePositive(const std::string& name, double value) const;
  void requireInRange(const std::string& name, double value, double lo, double hi) const;
  void requireOneOf(const std::string& name, const std::string& value, const std::vector<std::string>& allowed) const;
  // Throws ParameterError("parameter <ns>/<name>: <reason>") unless `reason` is empty (a config
  // struct's invalidReason()).
  void check(const std::string& name, const std::string& reason) const;

  // A parameter that was renamed: the name to read. The old name still works while the new one is
  // absent, with a warning naming both, so a team's config keeps starting after an update.
  std::string renamed(const std::string& now, const std::string& old) const;

  // What parameter `name` means, in a line ("[s] a command older than this is dropped"): written
  // beside the read, it is the meaning column of the generated parameter tables.
  void describe(const std::string& name, const std::string& meaning) const;

  // The values under `name` this reader leaves alone in this configuration (a disabled block's
  // settings, kept for when it is enabled again): they are not unknown keys.
  void unused(const std::string& name) const;

  // The values under this namespace no reader asked for, as "<qualified name> = <value>" lines
  // (a value inside a list of dictionaries is named "<list>[i]/<key>"), in key order.
  std::vector<std::string> unasked() const;
  // The names asked for directly under this namespace, present or not, sorted: what a reader knows.
  std::vector<std::string> askedKeys() const;
  // What the readers declared of each parameter under this namespace, by name relative to it; the
  // entries of a dictionary of named blocks (blockNames) are written "<dict>/<name>/...", the
  // dictionaries of a list (items) "<list>[]/...".
  std::map<std::string, ParameterDeclaration> declarations() const;
 private:
  void declare(const std::string& name, const std::string& type, bool required, const std::string& fallback) const;
  void declareRule(const std::string& name, const std::string& rule) const;
  XmlRpc::XmlRpcValue* find(const std::string& name) const;  // null when absent; remembers the name
  Params child(XmlRpc::XmlRpcValue tree, std::string ns) const;  // shares the names asked for
  void collectUnasked(XmlRpc::XmlRpcValue& v, const std::string& path, std::vector<std::string>& out) const;

  mutable XmlRpc::XmlRpcValue tree_;  // XmlRpcValue's lookups and conversions are not const
  std::string ns_;
  struct Asked {  // the qualified names asked for (a reader may run on any thread)
    std::mutex mutex;
    std::set<std::string> names;
    std::set<std::string> unused;  // whole subtrees (unused())
    std::map<std::string, ParameterDeclaration> declared;  // by qualified name
    std::set<std::string> block_maps;                      // dictionaries of named blocks (blockNames)
  };
  std::shared_ptr<Asked> asked_ = std::make_shared<Asked>();
};

}  // namespace robot_core
