#include "robot_core/parameters.h"

#include <sstream>

namespace robot_core {

std::string qualified(const ros::NodeHandle& pnh, const std::string& name) { return pnh.resolveName(name); }

namespace {

template <class T>
bool readTyped(const ros::NodeHandle& pnh, const std::string& name, T& out, const char* type_name) {
  if (!pnh.hasParam(name)) return false;
  if (!pnh.getParam(name, out))
    throw ParameterError("parameter " + qualified(pnh, name) + " has the wrong type: expected " + type_name);
  return true;
}

// Integers are accepted where a double is asked for (YAML `rate: 50`).
bool readNumber(const ros::NodeHandle& pnh, const std::string& name, double& out) {
  if (!pnh.hasParam(name)) return false;
  XmlRpc::XmlRpcValue v;
  pnh.getParam(name, v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    out = static_cast<double>(v);
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    out = static_cast<int>(v);
  } else {
    throw ParameterError("parameter " + qualified(pnh, name) + " has the wrong type: expected a number");
  }
  return true;
}

}  // namespace

double requireDouble(const ros::NodeHandle& pnh, const std::string& name) {
  double v = 0.0;
  if (!readNumber(pnh, name, v)) throw ParameterError("missing required parameter " + qualified(pnh, name) + " (a number)");
  return v;
}

int requireInt(const ros::NodeHandle& pnh, const std::string& name) {
  int v = 0;
  if (!readTyped(pnh, name, v, "an integer"))
    throw ParameterError("missing required parameter " + qualified(pnh, name) + " (an integer)");
  return v;
}

std::string requireString(const ros::NodeHandle& pnh, const std::string& name) {
  std::string v;
  if (!readTyped(pnh, name, v, "a string"))
    throw ParameterError("missing required parameter " + qualified(pnh, name) + " (a string)");
  return v;
}

double optionalDouble(const ros::NodeHandle& pnh, const std::string& name, double fallback) {
  double v = fallback;
  readNumber(pnh, name, v);
  return v;
}

int optionalInt(const ros::NodeHandle& pnh, const std::string& name, int fallback) {
  int v = fallback;
  readTyped(pnh, name, v, "an integer");
  return v;
}

bool optionalBool(const ros::NodeHandle& pnh, const std::string& name, bool fallback) {
  bool v = fallback;
  readTyped(pnh, name, v, "true or false");
  return v;
}

std::string optionalString(const ros::NodeHandle& pnh, const std::string& name, const std::string& fallback) {
  std::string v = fallback;
  readTyped(pnh, name, v, "a string");
  return v;
}

void requirePositive(const ros::NodeHandle& pnh, const std::string& name, double value) {
  if (!(value > 0.0)) {
    std::ostringstream s;
    s << "parameter " << qualified(pnh, name) << " = " << value << ": must be > 0";
    throw ParameterError(s.str());
  }
}

void requireInRange(const ros::NodeHandle& pnh, const std::string& name, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi)) {
    std::ostringstream s;
    s << "parameter " << qualified(pnh, name) << " = " << value << ": must be in [" << lo << ", " << hi << "]";
    throw ParameterError(s.str());
  }
}

void requireOneOf(const ros::NodeHandle& pnh, const std::string& name, const std::string& value,
                  const std::vector<std::string>& allowed) {
  for (const auto& a : allowed)
    if (a == value) return;
  std::ostringstream s;
  s << "parameter " << qualified(pnh, name) << " = '" << value << "': allowed values are";
  for (std::size_t i = 0; i < allowed.size(); ++i) s << (i ? ", " : " ") << allowed[i];
  throw ParameterError(s.str());
}

}  // namespace robot_core
