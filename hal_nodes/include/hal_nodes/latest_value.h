// The pull model's input side: keep only the newest message of a topic. A device samples it
// at its own rate, so a fast board never floods a slow device and nothing queues up.
//
//   LatestValue<hcl_drivers::ExampleBoardState> dial(nh, "/hcl/example_board/state", "dial");
//   if (auto m = dial.fresh(0.2)) use(*m);   // newest message if younger than 0.2 s
//
// Age is measured from the message's header stamp when it has one (the time of the board
// exchange: a latched, old message is old), otherwise from when it was received.
#pragma once

#include <ros/message_traits.h>
#include <ros/ros.h>
#include <robot_core/command_gate.h>

#include <functional>
#include <limits>
#include <mutex>
#include <string>

namespace hal_nodes {

// What a device's diagnostics need to know about one input, whatever its type.
class InputStatus {
 public:
  virtual ~InputStatus() = default;
  virtual const std::string& name() const = 0;
  virtual const std::string& topic() const = 0;
  virtual double age(const ros::Time& now) const = 0;  // +inf before the first message
  virtual unsigned long received() const = 0;
};

// The cache alone, without a subscription (testable without a ROS master).
template <class M>
class LatestValueCache {
 public:
  using ConstPtr = typename M::ConstPtr;

  // Returns the stamp the message's age counts from.
  ros::Time store(const ConstPtr& msg, const ros::Time& received_at) {
    std::lock_guard<std::mutex> lk(mutex_);
    msg_ = msg;
    stamp_ = stampOf(*msg, received_at);
    ++received_;
    return stamp_;
  }

  ConstPtr newest() const {
    std::lock_guard<std::mutex> lk(mutex_);
    return msg_;
  }

  // The newest message if it is at most max_age seconds old at `now`, else null.
  ConstPtr fresh(double max_age, const ros::Time& now) const {
    std::lock_guard<std::mutex> lk(mutex_);
    if (!msg_ || (now - stamp_).toSec() > max_age) return ConstPtr();
    return msg_;
  }

  double age(const ros::Time& now) const {
    std::lock_guard<std::mutex> lk(mutex_);
    return msg_ ? (now - stamp_).toSec() : std::numeric_limits<double>::infinity();
  }

  unsigned long received() const {
    std::lock_guard<std::mutex> lk(mutex_);
    return received_;
  }

  // The message's header stamp; null when its type has no header.
  static const ros::Time* headerStamp(const M& m) {
    return ros::message_traits::TimeStamp<M>::pointer(const_cast<M&>(m));
  }

 private:
  static ros::Time stampOf(const M& m, const ros::Time& received_at) {
    const ros::Time* stamp = headerStamp(m);
    return (stamp && !stamp->isZero()) ? *stamp : received_at;
  }

  mutable std::mutex mutex_;
  ConstPtr msg_;
  ros::Time stamp_;
  unsigned long received_ = 0;
};

// The cache fed by a queue-1 subscription.
template <class M>
class LatestValue : public InputStatus {
 public:
  using ConstPtr = typename M::ConstPtr;

  // `on_arrival` (optional) runs after each message is stored, with the message's header stamp,
  // the board exchange it comes from; zero when it has none (a velocity command: each message
  // is news of its own, however close in time to the last): it wakes the reading device.
  using OnArrival = std::function<void(const ros::Time& stamp)>;
  // `command`: a command topic (a velocity, a lamp): its messages pass robot_core's CommandGate
  // first, so a sender outside the robot's network is not obeyed during a match.
  LatestValue(ros::NodeHandle& nh, const std::string& topic, std::string name, OnArrival on_arrival = nullptr,
              bool command = false)
      : name_(std::move(name)), topic_(nh.resolveName(topic)), on_arrival_(std::move(on_arrival)) {
    if (command) robot_core::CommandGate::instance();  // now: it must know the match before the first command
    ros::SubscribeOptions ops;
    ops.template initByFullCallbackType<const ros::MessageEvent<M const>&>(
        topic_, 1, [this, command](const ros::MessageEvent<M const>& event) {
          if (command && !robot_core::CommandGate::instance().accept(event.getPublisherName(), topic_)) return;
          const ConstPtr& m = event.getConstMessage();
          cache_.store(m, ros::Time::now());
          if (on_arrival_) {
            const ros::Time* own = LatestValueCache<M>::headerStamp(*m);
            on_arrival_(own ? *own : ros::Time());
          }
        });
    ops.transport_hints = ros::TransportHints().tcpNoDelay();
    sub_ = nh.subscribe(ops);
  }

  ConstPtr newest() const { return cache_.newest(); }
  ConstPtr fresh(double max_age) const { return cache_.fresh(max_age, ros::Time::now()); }
  double age() const { return cache_.age(ros::Time::now()); }

  const std::string& name() const override { return name_; }
  const std::string& topic() const override { return topic_; }
  double age(const ros::Time& now) const override { return cache_.age(now); }
  unsigned long received() const override { return cache_.received(); }

 private:
  std::string name_;
  std::string topic_;
  OnArrival on_arrival_;
  LatestValueCache<M> cache_;
  ros::Subscriber sub_;
};

}  // namespace hal_nodes
