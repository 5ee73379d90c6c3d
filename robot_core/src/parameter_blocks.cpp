#include "robot_core/parameter_blocks.h"

namespace robot_core {
inline namespace parameter_reader {

std::vector<std::string> optionalBlockNames(const ros::NodeHandle& pnh, const std::string& name) {
  std::vector<std::string> out;
  if (!pnh.hasParam(name)) return out;
  XmlRpc::XmlRpcValue v;
  pnh.getParam(name, v);
  if (v.getType() != XmlRpc::XmlRpcValue::TypeStruct)
    throw ParameterError("parameter " + qualified(pnh, name) + " must be a dictionary of named blocks");
  for (auto& e : v) {
    if (e.second.getType() != XmlRpc::XmlRpcValue::TypeStruct)
      throw ParameterError("parameter " + qualified(pnh, name + "/" + e.first) + " must be a dictionary");
    out.push_back(e.first);
  }
  return out;
}

std::vector<std::string> requireBlockNames(const ros::NodeHandle& pnh, const std::string& name) {
  if (!pnh.hasParam(name))
    throw ParameterError("missing required parameter " + qualified(pnh, name) + " (a dictionary of named blocks)");
  auto out = optionalBlockNames(pnh, name);
  if (out.empty()) throw ParameterError("parameter " + qualified(pnh, name) + " must name at least one block");
  return out;
}

std::vector<double> optionalDoubleList(const ros::NodeHandle& pnh, const std::string& name,
                                       const std::vector<double>& fallback) {
  if (!pnh.hasParam(name)) return fallback;
  XmlRpc::XmlRpcValue v;
  pnh.getParam(name, v);
  const std::string err = "parameter " + qualified(pnh, name) + " must be a list of numbers";
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray) throw ParameterError(err);
  std::vector<double> out;
  for (int i = 0; i < v.size(); ++i) {
    if (v[i].getType() == XmlRpc::XmlRpcValue::TypeDouble)
      out.push_back(static_cast<double>(v[i]));
    else if (v[i].getType() == XmlRpc::XmlRpcValue::TypeInt)
      out.push_back(static_cast<int>(v[i]));
    else
      throw ParameterError(err);
  }
  return out;
}

std::vector<std::pair<std::string, int>> optionalIntMap(const ros::NodeHandle& pnh, const std::string& name) {
  std::vector<std::pair<std::string, int>> out;
  if (!pnh.hasParam(name)) return out;
  XmlRpc::XmlRpcValue v;
  pnh.getParam(name, v);
  const std::string err = "parameter " + qualified(pnh, name) + " must be a dictionary name: index (integers >= 0)";
  if (v.getType() != XmlRpc::XmlRpcValue::TypeStruct) throw ParameterError(err);
  for (auto& e : v) {
    if (e.second.getType() != XmlRpc::XmlRpcValue::TypeInt || static_cast<int>(e.second) < 0) throw ParameterError(err);
    out.emplace_back(e.first, static_cast<int>(e.second));
  }
  return out;
}

std::vector<std::string> optionalStringList(const ros::NodeHandle& pnh, const std::string& name,
                                            const std::vector<std::string>& fallback) {
  if (!pnh.hasParam(name)) return fallback;
  std::vector<std::string> out;
  if (!pnh.getParam(name, out))
    throw ParameterError("parameter " + qualified(pnh, name) + " must be a list of strings");
  return out;
}

}  // namespace parameter_reader
}  // namespace robot_core
