#include "robot_sim/firmware/firmware_host.h"

#include "robot_sim/firmware/channel_check.h"
#include "robot_sim/firmware/firmware_check.h"
#include "robot_sim/firmware/firmware_registry.h"

namespace robot_sim {

FirmwareHost::FirmwareHost(ros::NodeHandle nh, ros::NodeHandle pnh, World* world)
    : nh_(std::move(nh)), pnh_(std::move(pnh)), world_(world) {}

FirmwareHost::~FirmwareHost() { stopAll(); }

bool FirmwareHost::startFromParameters() {
  XmlRpc::XmlRpcValue all;
  if (!pnh_.getParam(pnh_.getNamespace(), all) || all.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    ROS_FATAL("no emulators configured under %s", pnh_.getNamespace().c_str());
    return false;
  }
  const std::vector<std::string> taken = channelsInUse(all);
  if (!taken.empty()) {
    std::string list;
    for (const auto& t : taken) list += (list.empty() ? "" : "; ") + t;
    ROS_FATAL("refusing to start: another simulation runs on this one's channels (%s). Give each simulation "
              "running at the same time its own channels (launch arguments can_bus, sim_dir, camera_port)",
              list.c_str());
    return false;
  }
  for (auto& entry : all) {
    const std::string param = pnh_.getNamespace() + "/" + entry.first;
    const ros::NodeHandle own(pnh_, entry.first);
    const robot_core::Params params(entry.second, own.getNamespace());
    std::string type;
    try {
      if (!isStartedEmulatorBlock(params)) continue;
      type = params.requireString("type");
    } catch (const std::exception& e) {
      ROS_FATAL("%s", e.what());
      return false;
    }
    auto fw = FirmwareRegistry::instance().create(type);
    if (!fw) {
      ROS_FATAL("%s", unknownEmulatorType(params, type).c_str());
      return false;
    }
    FirmwareContext ctx{nh_, own, params, entry.first, world_};
    try {
      fw->configure(ctx.params);
      fw->start(ctx);
    } catch (const std::exception& e) {
      ROS_FATAL("emulator %s failed to start: %s", param.c_str(), e.what());
      return false;
    }
    ROS_INFO("emulating board %s (%s)", entry.first.c_str(), type.c_str());
    firmware_[entry.first] = std::move(fw);
  }
  return true;
}

Firmware* FirmwareHost::find(const std::string& name) const {
  auto it = firmware_.find(name);
  return it == firmware_.end() ? nullptr : it->second.get();
}

void FirmwareHost::stopAll() {
  for (auto& kv : firmware_) kv.second->stop();
  firmware_.clear();
}

}  // namespace robot_sim
