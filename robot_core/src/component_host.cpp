#include "robot_core/component_host.h"

#include "robot_core/host_settings.h"
#include "robot_core/params.h"
#include "robot_core/realtime.h"

#include <nodelet/nodelet.h>
#include <pluginlib/class_loader.hpp>

#include <algorithm>
#include <sstream>

namespace robot_core {

ComponentHost::ComponentHost(std::string package, std::string kind)
    : package_(std::move(package)), kind_(std::move(kind)), loader_(std::make_unique<nodelet::Loader>(true)) {}

std::vector<std::string> ComponentHost::declaredTypes(const std::string& package) {
  pluginlib::ClassLoader<nodelet::Nodelet> classes("nodelet", "nodelet::Nodelet");
  std::vector<std::string> out;
  const std::string prefix = package + "/";
  for (const auto& c : classes.getDeclaredClasses())
    if (c.rfind(prefix, 0) == 0) out.push_back(c.substr(prefix.size()));
  std::sort(out.begin(), out.end());
  return out;
}

bool ComponentHost::loadFromParameters(const ros::NodeHandle& pnh) {
  XmlRpc::XmlRpcValue all;
  if (!pnh.getParam(pnh.getNamespace(), all) || all.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    ROS_FATAL("no %ss configured under %s (load config/<robot>.yaml into that namespace)", kind_.c_str(),
              pnh.getNamespace().c_str());
    return false;
  }
  // Its own values (its real-time threads' priority, ~only) before any component starts one.
  HostSettings settings;
  try {
    settings = HostSettings::read(Params(all, pnh.getNamespace()), kind_);
  } catch (const ParameterError& e) {
    ROS_FATAL("%s", e.what());
    return false;
  }
  setRealtimePriority(settings.realtime_priority);
  // What this host publishes on /diagnostics is said once everything is loaded: a status that
  // never came (a device stuck before its first report) is then missing, not merely absent.
  pnh.deleteParam("status_names");
  const std::vector<std::string> types = availableTypes();
  const std::vector<std::string>& only = settings.only;
  for (auto& entry : all) {
    const std::string& key = entry.first;
    XmlRpc::XmlRpcValue& block = entry.second;
    if (block.getType() != XmlRpc::XmlRpcValue::TypeStruct || !block.hasMember("type")) continue;
    const std::string param = pnh.getNamespace() + "/" + key;
    if (!only.empty() && std::find(only.begin(), only.end(), key) == only.end()) continue;
    if (block.hasMember("enabled") && block["enabled"].getType() == XmlRpc::XmlRpcValue::TypeBoolean &&
        !static_cast<bool>(block["enabled"])) {
      ROS_INFO("%s %s disabled in config", kind_.c_str(), param.c_str());
      continue;
    }
    if (block["type"].getType() != XmlRpc::XmlRpcValue::TypeString) {
      ROS_FATAL("parameter %s/type must be a string", param.c_str());
      return false;
    }
    const std::string type = static_cast<std::string>(block["type"]);
    if (std::find(types.begin(), types.end(), type) == types.end()) {
      std::ostringstream allowed;
      for (std::size_t i = 0; i < types.size(); ++i) allowed << (i ? ", " : "") << types[i];
      ROS_FATAL("parameter %s/type = '%s': unknown %s type; allowed values: %s", param.c_str(), type.c_str(),
                kind_.c_str(), allowed.str().c_str());
      return false;
    }
    nodelet::M_string remappings;
    nodelet::V_string argv;
    if (!loader_->load(param, package_ + "/" + type, remappings, argv)) {
      ROS_FATAL("%s %s (%s) failed to start; see the line above", kind_.c_str(), param.c_str(), type.c_str());
      return false;
    }
    loaded_.push_back(param);
  }
  if (loaded_.empty()) {
    ROS_FATAL("no enabled %ss found under %s: each needs a block with a `type`", kind_.c_str(),
              pnh.getNamespace().c_str());
    return false;
  }
  std::vector<std::string> status_names;  // as diagnostic_updater names them: "hal/odometry: device"
  for (const auto& param : loaded_) status_names.push_back(param.substr(param[0] == '/' ? 1 : 0) + ": " + kind_);
  pnh.setParam("status_names", status_names);
  ROS_INFO("%s: %zu %s(s) running", pnh.getNamespace().c_str(), loaded_.size(), kind_.c_str());
  return true;
}

}  // namespace robot_core
