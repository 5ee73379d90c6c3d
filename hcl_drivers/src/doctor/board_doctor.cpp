// The hardware doctor's engine: checks every board configured under ~hcl_ns (default /hcl) on
// its real channel, without starting the product, then each CAN and I2C bus as a whole
// (bus_checks.h), and prints the findings as one JSON array on stdout. `rosrun hcl_drivers
// doctor ROBOT` (scripts/doctor) loads the config into a private master, runs this and prints
// the table. Each board type checks itself: Board::check(), loaded through the same nodelet
// plugins as the HCL.
//   ~hcl_ns        where the board blocks are (default /hcl)
//   ~computer_ns   the config's computer section: CAN bitrates (default /computer)
//   ~boards        only these blocks, comma-separated (default: all with a type and not `enabled: false`)
//   ~load_window   [s] listening for each CAN bus's load and errors (default 2)
#include <nodelet/nodelet.h>
#include <pluginlib/class_loader.hpp>
#include <ros/ros.h>

#include <algorithm>
#include <iostream>
#include <map>
#include <sstream>

#include "bus_checks.h"
#include "hcl_drivers/board_nodelet.h"

namespace {

using hcl_drivers::CheckReport;
using hcl_drivers::CheckRow;

std::string json(const std::string& s) {
  std::ostringstream o;
  o << '"';
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') o << '\\' << c;
    else if (c == '\n') o << "\\n";
    else if (c < 0x20) o << ' ';
    else o << c;
  }
  o << '"';
  return o.str();
}

double number(XmlRpc::XmlRpcValue& v, double fallback) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(v);
  return fallback;
}

void print(const std::vector<CheckRow>& rows) {
  std::cout << "[\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    std::cout << "  {\"board\": " << json(r.board) << ", \"check\": " << json(r.item) << ", \"expected\": " << json(r.expected)
              << ", \"found\": " << json(r.found) << ", \"status\": " << json(toString(r.level)) << ", \"hint\": " << json(r.hint)
              << "}" << (i + 1 < rows.size() ? "," : "") << "\n";
  }
  std::cout << "]" << std::endl;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "hcl_doctor", ros::init_options::AnonymousName | ros::init_options::NoRosout);
  ros::NodeHandle pnh("~");
  // Its own values, set by the doctor script from its command line.
  std::string hcl_ns, computer_ns, boards;
  double load_window = 2.0;
  try {
    const robot_core::Params own = robot_core::Params::of(pnh);
    own.describe("hcl_ns", "the namespace of the robot's board blocks");
    hcl_ns = own.optionalString("hcl_ns", "/hcl");
    own.describe("computer_ns", "the namespace of the robot's computer block (its CAN interfaces)");
    computer_ns = own.optionalString("computer_ns", "/computer");
    own.describe("load_window", "[s] how long each CAN bus's load is measured");
    load_window = own.optionalDouble("load_window", 2.0);
    own.requirePositive("load_window", load_window);
    own.describe("boards", "the boards to check, comma-separated (_boards:=a,b); empty: every board");
    boards = own.optionalString("boards", "");
  } catch (const std::exception& e) {
    std::cerr << "doctor: " << e.what() << std::endl;
    return 2;
  }
  std::vector<std::string> only;
  std::stringstream names(boards);
  for (std::string name; std::getline(names, name, ',');)
    if (!name.empty()) only.push_back(name);
  // The board blocks are walked as data (which channel each one uses); each board reads its own
  // block with its configure() below.
  XmlRpc::XmlRpcValue blocks, computer;
  if (!ros::param::get(hcl_ns, blocks) || blocks.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    std::cerr << "doctor: no board blocks under " << hcl_ns << std::endl;
    return 2;
  }
  ros::param::get(computer_ns, computer);

  pluginlib::ClassLoader<nodelet::Nodelet> loader("nodelet", "nodelet::Nodelet");
  std::vector<std::unique_ptr<CheckReport>> reports, others;
  std::map<std::string, std::vector<CheckReport*>> can_buses, i2c_buses;
  for (auto& block : blocks) {
    const std::string name = block.first;
    XmlRpc::XmlRpcValue& b = block.second;
    if (b.getType() != XmlRpc::XmlRpcValue::TypeStruct || !b.hasMember("type")) continue;
    if (b.hasMember("enabled") && b["enabled"].getType() == XmlRpc::XmlRpcValue::TypeBoolean && !static_cast<bool>(b["enabled"]))
      continue;
    if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) {
      // Not checked, but configured: its node id or address is no stranger to the bus scan.
      others.push_back(std::make_unique<CheckReport>(name));
      CheckReport& other = *others.back();
      const bool can = b.hasMember("node_id"), i2c = b.hasMember("address");
      if (b.hasMember("bus") && b["bus"].getType() == XmlRpc::XmlRpcValue::TypeString && (can || i2c)) {
        other.channel = {can ? "can" : "i2c", static_cast<std::string>(b["bus"]),
                         static_cast<int>(number(b[can ? "node_id" : "address"], -1)), true};
        (can ? can_buses : i2c_buses)[other.channel.bus].push_back(&other);
      }
      continue;
    }
    reports.push_back(std::make_unique<CheckReport>(name));
    CheckReport& report = *reports.back();
    const std::string type = static_cast<std::string>(b["type"]);
    try {
      auto plugin = loader.createUniqueInstance("hcl_drivers/" + type);
      auto* host = dynamic_cast<hcl_drivers::BoardNodeletBase*>(plugin.get());
      if (!host) throw std::runtime_error("hcl_drivers/" + type + " is not a board");
      std::unique_ptr<hcl_drivers::Board> board = host->newBoard();
      hcl_drivers::BoardContext ctx{ros::NodeHandle(), ros::NodeHandle(hcl_ns + "/" + name), hcl_ns + "/" + name,
                                    b.hasMember("rate") ? number(b["rate"], 10.0) : 10.0, {}};
      board->configure(robot_core::Params::of(ctx.pnh));
      board->check(ctx, report);
    } catch (const pluginlib::PluginlibException& e) {
      report.fail("type", type, "no such board type", "`rosrun nodelet declared_nodelets` lists the hcl_drivers/ types");
    } catch (const std::exception& e) {
      report.fail("config", "a valid block", e.what(), "fix the block in the robot's config");
    }
    if (report.channel.kind == "can") can_buses[report.channel.bus].push_back(&report);
    if (report.channel.kind == "i2c") i2c_buses[report.channel.bus].push_back(&report);
  }
  std::vector<CheckRow> bus_rows;
  // Only the buses of the boards checked (~boards): another bus is not this run's business.
  auto checked = [&](const std::vector<CheckReport*>& on_bus) {
    return std::any_of(on_bus.begin(), on_bus.end(), [&](const CheckReport* r) {
      return std::any_of(reports.begin(), reports.end(), [r](const auto& own) { return own.get() == r; });
    });
  };
  for (auto& bus : can_buses)
    if (checked(bus.second)) hcl_drivers::doctor::checkCanBus(bus.first, bus.second, computer, load_window, bus_rows);
  for (auto& bus : i2c_buses)
    if (checked(bus.second)) hcl_drivers::doctor::checkI2cBus(bus.first, bus.second, bus_rows);
  std::vector<CheckRow> rows;
  for (const auto& r : reports) rows.insert(rows.end(), r->rows().begin(), r->rows().end());
  rows.insert(rows.end(), bus_rows.begin(), bus_rows.end());
  print(rows);
  return 0;
}
