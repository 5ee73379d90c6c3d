// ExampleBoard: the skeleton robot's board. A dial (10-bit ADC) in, a lamp (8-bit PWM) out,
// over UDP (example_protocol.h). Copy this file to start a new board.
//
// Parameters (besides the common ones in board_nodelet.h): read and described, each with a
// p.describe() beside its read, in configure() (the table: hcl_drivers/PARAMETERS.md, make docs).
// The ~command_timeout is the pattern every actuator board follows: a stale command is dropped
// and the actuator made safe.
// Topics: ~state (hcl_drivers/ExampleBoardState, latched), ~lamp_pwm (std_msgs/UInt8, in).
#include <hcl_drivers/ExampleBoardState.h>
#include <std_msgs/UInt8.h>

#include <memory>
#include <mutex>

#include <robot_core/priority_inheritance_mutex.h>

#include "hcl_drivers/board_nodelet.h"
#include "hcl_drivers/boards/example_protocol.h"
#include "hcl_drivers/transport/endpoint.h"
#include "hcl_drivers/transport/udp_socket.h"

namespace hcl_drivers {

using robot_core::ParameterError;

class ExampleBoard : public Board {
 public:
  // Every parameter, into members, validated; nothing else (no socket, no topic): it also runs
  // with no master and no board (check_config, the doctor).
  void configure(const robot_core::Params& p) override {
    p.describe("endpoint", "udp://HOST:PORT of the board");
    url_ = p.requireString("endpoint");
    try {
      endpoint_ = transport::parseEndpoint(url_);
    } catch (const std::invalid_argument& e) {
      throw ParameterError("parameter " + p.qualified("endpoint") + ": " + e.what());
    }
    if (endpoint_.scheme != "udp") throw ParameterError("parameter " + p.qualified("endpoint") + " = '" + url_ + "': the example board speaks udp://HOST:PORT only");
    // The polling rate, for the default below: required and checked by the framework
    // (BoardSettings) before configure(); the doctor polls nothing and takes 10 Hz when absent.
    p.describe("rate", "[Hz] polling rate of the board");
    const double rate = p.optionalDouble("rate", 10.0);
    p.requirePositive("rate", rate);
    p.describe("answer_timeout", "[s] how long to wait for the board's answer");
    answer_timeout_ = p.optionalDouble("answer_timeout", std::min(0.02, 0.5 / rate));
    p.requirePositive("answer_timeout", answer_timeout_);
    p.describe("command_timeout", "[s] a lamp command older than this is dropped and the lamp switched off");
    command_timeout_ = p.optionalDouble("command_timeout", 0.5);
    p.requirePositive("command_timeout", command_timeout_);
  }

  // Opens the channel, advertises and subscribes, with what configure() read.
  void init(BoardContext& ctx) override {
    socket_ = std::make_unique<transport::UdpSocket>(endpoint_.host, endpoint_.port);
    state_pub_ = ctx.pnh.advertise<ExampleBoardState>("state", 1, true);
    lamp_sub_ = subscribeCommand<std_msgs::UInt8>(ctx, "lamp_pwm", [this](const std_msgs::UInt8::ConstPtr& m) { onLamp(m); });
  }

  // The doctor: one request with the lamp off (its safe state) must get a well-formed answer.
  void check(BoardContext& /*ctx*/, CheckReport& report) override {
    const std::string& url = url_;
    transport::UdpSocket socket(endpoint_.host, endpoint_.port);
    if (!socket.send(example_protocol::encodeRequest(1, 0))) {
      report.fail("answer", "an answer from " + url, socket.lastError(), "is the board's network up (ping its address)?");
      return;
    }
    std::vector<uint8_t> datagram;
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(0.5);
    int malformed = 0;
    for (double left = 0.5; left > 0.0; left = (deadline - ros::WallTime::now()).toSec()) {
      if (!socket.receive(datagram, left)) break;
      if (example_protocol::decodeReply(datagram)) {
        report.ok("answer", "an answer from " + url, "answers" + (malformed ? " (after " + std::to_string(malformed) + " malformed)" : std::string()));
        return;
      }
      ++malformed;
    }
    report.fail("answer", "an answer from " + url, malformed ? std::to_string(malformed) + " malformed answers" : "no answer in 0.5 s",
                "is the board powered and at this address and port?");
  }

  bool service() override {
    const uint8_t lamp = lampToApply();
    const uint8_t seq = ++seq_;
    socket_->drain();  // answers to earlier requests that timed out
    if (!socket_->send(example_protocol::encodeRequest(seq, lamp))) {
      fail(socket_->lastError());
      return false;
    }
    std::vector<uint8_t> datagram;
    // The reply window is wall time: the board (or its emulator) answers in wall time.
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(answer_timeout_);
    while (true) {
      const double left = (deadline - ros::WallTime::now()).toSec();
      if (left <= 0.0 || !socket_->receive(datagram, left)) {
        fail("no answer: " + socket_->lastError());
        return false;
      }
      const auto reply = example_protocol::decodeReply(datagram);
      if (!reply) {
        std::lock_guard lk(mutex_);
        ++malformed_;  // counted and dropped; keep waiting for the real answer
        continue;
      }
      if (reply->seq != seq) continue;  // a late answer to an older request
      publish(*reply);
      return true;
    }
  }

  void halt() override {
    {
      std::lock_guard lk(mutex_);
      lamp_command_ = 0;
      lamp_stamp_ = ros::Time();
    }
    if (socket_) socket_->send(example_protocol::encodeRequest(++seq_, 0));  // best effort: lamp off
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard lk(mutex_);
    stat.add("malformed answers", malformed_);
    stat.add("board resets seen", resets_);
    stat.add("commands dropped as stale", stale_commands_);
    stat.add("lamp pwm commanded", static_cast<int>(lamp_command_));
  }

 private:
  void onLamp(const std_msgs::UInt8::ConstPtr& msg) {
    std::lock_guard lk(mutex_);
    lamp_command_ = msg->data;
    lamp_stamp_ = ros::Time::now();
  }

  // The commanded PWM, or 0 when the last command is older than ~command_timeout.
  uint8_t lampToApply() {
    std::lock_guard lk(mutex_);
    if (lamp_stamp_.isZero()) return 0;
    if ((ros::Time::now() - lamp_stamp_).toSec() > command_timeout_) {
      ++stale_commands_;
      lamp_stamp_ = ros::Time();
      lamp_command_ = 0;
      ROS_WARN("example board: no lamp command for %.2f s, lamp off", command_timeout_);
      return 0;
    }
    return lamp_command_;
  }

  void publish(const example_protocol::Reply& r) {
    if (have_uptime_ && r.uptime_ms < last_uptime_) {
      std::lock_guard lk(mutex_);
      ++resets_;
      ROS_WARN("example board reset (uptime %u ms -> %u ms)", last_uptime_, r.uptime_ms);
    }
    have_uptime_ = true;
    last_uptime_ = r.uptime_ms;
    ExampleBoardState::Ptr s(new ExampleBoardState);
    s->header.stamp = ros::Time::now();
    s->dial_raw = r.dial_raw;
    s->lamp_pwm = r.lamp_pwm;
    s->uptime_ms = r.uptime_ms;
    state_pub_.publish(s);
  }

  std::string url_;  // ~endpoint
  transport::Endpoint endpoint_;
  std::unique_ptr<transport::UdpSocket> socket_;
  ros::Publisher state_pub_;
  ros::Subscriber lamp_sub_;
  double answer_timeout_ = 0.02;
  double command_timeout_ = 0.5;
  uint8_t seq_ = 0;
  bool have_uptime_ = false;
  uint32_t last_uptime_ = 0;

  robot_core::PriorityInheritanceMutex mutex_;  // command callback vs polling thread vs diagnostics
  uint8_t lamp_command_ = 0;
  ros::Time lamp_stamp_;
  unsigned long malformed_ = 0;
  unsigned long resets_ = 0;
  unsigned long stale_commands_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(ExampleBoard,
                 "Skeleton example board over UDP: a dial (ADC) in, a lamp (PWM) out.")
