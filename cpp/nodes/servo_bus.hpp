// What the STS3215 nodes share: a bus built from node parameters, and riding out a lost port.
//
// BusGuard::call runs one bus operation per control tick. While the port is gone it logs (at most
// every LOG_INTERVAL), lets the driver try to reopen it no more often than every RECONNECT_INTERVAL,
// and raises DeviceError (exit code 3) once the bus has been failing for DEVICE_LOST_GRACE.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "drivers/sts3215_bus.hpp"
#include "joshua_rcl/node.hpp"
#include "sensor_msgs/msg/joint_state.hpp"

namespace joshua {

// An unopened bus for serial_port, baud_rate, device_ids, joint_names and calibration_file.
std::unique_ptr<Sts3215Bus> bus_from_parameters(const Parameters& parameters, std::vector<std::string>& joint_names);

// 1 / rate_hz; SettingsError unless rate_hz is positive.
double period_s(const Parameters& parameters);

// Now on the wall clock (what a node's ROS clock gives), for message headers.
builtin_interfaces::msg::Time wall_clock_stamp();

// A JointState of the bus's readings, stamped now (wall clock) with `frame_id`.
sensor_msgs::msg::JointState joint_state(const std::vector<std::string>& joint_names,
                                         const std::vector<JointReading>& readings, const std::string& frame_id);

// Goal positions in `joint_names` order from a JointState (NaN where a joint is absent); empty when the
// message carries no positions. A message without names is taken in bus order when its length matches.
std::vector<double> goals_from(const sensor_msgs::msg::JointState& message, const std::vector<std::string>& joint_names);

class BusGuard {
 public:
  BusGuard(Sts3215Bus& bus, const Node& node, std::function<void()> on_reconnect);
  // Runs `operation`; false while the bus is failing (DeviceError once past the grace period).
  bool call(const std::function<void()>& operation);
  // Why the last failing operation failed ("" when none has failed).
  const std::string& last_error() const { return last_error_; }

 private:
  void failed(Clock::time_point now, const DeviceError& error);
  void check_grace(Clock::time_point now);

  Sts3215Bus& bus_;
  const Node& node_;
  std::function<void()> on_reconnect_;
  int connections_;
  bool failing_ = false;
  Clock::time_point failing_since_, next_attempt_, next_log_;
  std::string last_error_;
};

}  // namespace joshua
