// Bumpers: named contacts (bumpers, end switches the brain cares about) read from one or
// more boards' hcl_drivers/DigitalInputs, published as hal_nodes/Contacts on ~contacts
// (/hal/bumpers/contacts) at the device rate, with the edges since the previous message.
// A contact is found by the board's input name (`input`) or by its bit number (`bit`).
// While a board is stale its contacts are unknown: they are left out of `closed`, no edges
// are invented, and the device is unavailable naming the board.
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <hal_nodes/Contacts.h>
#include <hcl_drivers/DigitalInputs.h>

#include <algorithm>
#include <map>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/devices/contact_input.h"
#include <robot_core/params.h>

namespace hal_nodes {

class BumpersDevice : public Device {
 public:
  void configure(const robot_core::Params& params) override {
    params.describe("max_input_age", "[s] a board whose inputs are older is stale: its contacts are unknown");
    max_input_age_ = params.optionalDouble("max_input_age", 0.5);
    params.requirePositive("max_input_age", max_input_age_);
    contacts_.clear();
    params.describe("contacts", "the switches by name: {topic, input or bit, invert} each (contact_input.h)");
    for (const auto& name : params.requireBlockNames("contacts")) {
      Contact c;
      c.name = name;
      const ContactSpec spec = ContactSpec::read(params, "contacts/" + name);
      c.board = spec.topic;
      c.input = spec.input;
      c.bit = spec.bit;
      c.invert = spec.invert;
      contacts_.push_back(std::move(c));
    }
  }

  void init(DeviceContext& ctx) override {
    using namespace hcl_drivers;  // the boards' messages
    for (const auto& c : contacts_)
      if (!boards_.count(c.board)) boards_[c.board] = addInput<DigitalInputs>(ctx.nh, c.board, c.board);
    pub_ = ctx.pnh.advertise<Contacts>("contacts", 10);
  }

  void refresh() override {
    Contacts out;
    out.header.stamp = ros::Time::now();
    std::string stale;
    for (auto& [topic, input] : boards_)
      if (!input->fresh(max_input_age_)) stale += (stale.empty() ? "" : ", ") + topic;
    for (auto& c : contacts_) {
      const auto m = boards_[c.board]->fresh(max_input_age_);
      if (!m) {
        c.known = false;
        continue;
      }
      int bit = c.bit;
      if (!c.input.empty()) {
        const auto it = std::find(m->names.begin(), m->names.end(), c.input);
        if (it == m->names.end()) {
          c.known = false;
          stale += (stale.empty() ? "" : ", ") + ("input '" + c.input + "' not reported by " + c.board);
          continue;
        }
        bit = static_cast<int>(it - m->names.begin());
      }
      const bool closed = (((m->bits >> bit) & 1u) != 0) != c.invert;
      if (closed) out.closed.push_back(c.name);
      if (c.known && closed && !c.closed) out.pressed.push_back(c.name);
      if (c.known && !closed && c.closed) out.released.push_back(c.name);
      c.closed = closed;
      c.known = true;
    }
    if (stale.empty()) setAvailable();
    else setUnavailable("no fresh inputs from: " + stale);
    pub_.publish(out);
  }

 private:
  struct Contact {
    std::string name, board, input;
    int bit = -1;
    bool invert = false;
    bool known = false, closed = false;
  };
  std::map<std::string, std::shared_ptr<LatestValue<hcl_drivers::DigitalInputs>>> boards_;
  std::vector<Contact> contacts_;
  ros::Publisher pub_;
  double max_input_age_ = 0.5;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(BumpersDevice, Bumpers,
                  "Bumpers: named contacts from boards' digital inputs, with pressed/released edges.")
