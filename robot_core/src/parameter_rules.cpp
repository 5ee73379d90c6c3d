#include "parameter_rules.h"

#include <cmath>
#include <sstream>

#include "robot_core/parameter_error.h"

namespace robot_core {

namespace rules {

// The value as the user wrote it (YAML-ish), for the error line: a refused value is always quoted.
std::string quote(XmlRpc::XmlRpcValue& v) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeString: return "'" + static_cast<std::string>(v) + "'";
    case XmlRpc::XmlRpcValue::TypeBoolean: return static_cast<bool>(v) ? "true" : "false";
    case XmlRpc::XmlRpcValue::TypeInt: return std::to_string(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble: {
      std::ostringstream s;
      s << static_cast<double>(v);
      return s.str();
    }
    case XmlRpc::XmlRpcValue::TypeArray: return "a list of " + std::to_string(v.size());
    case XmlRpc::XmlRpcValue::TypeStruct: return "a dictionary";
    default: return "an unreadable value";
  }
}

namespace {
[[noreturn]] void wrongType(XmlRpc::XmlRpcValue& v, const std::string& name, const char* expected) {
  throw ParameterError("parameter " + name + " = " + quote(v) + " has the wrong type: expected " + expected);
}
}  // namespace

double toNumber(XmlRpc::XmlRpcValue& v, const std::string& name) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(v);
  wrongType(v, name, "a number");
}

int toInt(XmlRpc::XmlRpcValue& v, const std::string& name) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(v);
  // roscpp's getParam(int) takes 2.0 too (it rounds any double): a whole number passes, 2.5 is refused
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    const double d = static_cast<double>(v);
    if (std::floor(d) == d && std::abs(d) < 2147483648.0) return static_cast<int>(d);
  }
  wrongType(v, name, "an integer");
}

bool toBool(XmlRpc::XmlRpcValue& v, const std::string& name) {
  if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean) wrongType(v, name, "true or false");
  return static_cast<bool>(v);
}

std::string toString(XmlRpc::XmlRpcValue& v, const std::string& name) {
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString) wrongType(v, name, "a string");
  return static_cast<std::string>(v);
}

void missing(const std::string& name, const char* what) {
  throw ParameterError("missing required parameter " + name + " (" + what + ")");
}

void positive(const std::string& name, double value) {
  if (!(value > 0.0)) {
    std::ostringstream s;
    s << "parameter " << name << " = " << value << ": must be > 0";
    throw ParameterError(s.str());
  }
}

void inRange(const std::string& name, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi)) {
    std::ostringstream s;
    s << "parameter " << name << " = " << value << ": must be in [" << lo << ", " << hi << "]";
    throw ParameterError(s.str());
  }
}

void oneOf(const std::string& name, const std::string& value, const std::vector<std::string>& allowed) {
  for (const auto& a : allowed)
    if (a == value) return;
  std::ostringstream s;
  s << "parameter " << name << " = '" << value << "': allowed values are";
  for (std::size_t i = 0; i < allowed.size(); ++i) s << (i ? ", " : " ") << allowed[i];
  throw ParameterError(s.str());
}

}  // namespace rules
}  // namespace robot_core
