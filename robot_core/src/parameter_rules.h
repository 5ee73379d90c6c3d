// The rules both readers apply , so a value
// is accepted or refused, with the same line, whichever way it is read.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

namespace robot_core {
namespace rules {

// The value as the user wrote it (YAML-ish), for an error line: a refused value is always quoted.
std::string quote(XmlRpc::XmlRpcValue& v);

// A present value as the type asked for, or ParameterError("parameter <name> has the wrong
// type: expected ..."). Integers are accepted where a number is asked for (YAML `rate: 50`).
double toNumber(XmlRpc::XmlRpcValue& v, const std::string& name);
int toInt(XmlRpc::XmlRpcValue& v, const std::string& name);
bool toBool(XmlRpc::XmlRpcValue& v, const std::string& name);
std::string toString(XmlRpc::XmlRpcValue& v, const std::string& name);

[[noreturn]] void missing(const std::string& name, const char* what);
void positive(const std::string& name, double value);
void inRange(const std::string& name, double value, double lo, double hi);
void oneOf(const std::string& name, const std::string& value, const std::vector<std::string>& allowed);

}  // namespace rules
}  // namespace robot_core
