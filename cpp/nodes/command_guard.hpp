// Guards for an actuator's goals, free of ROS: a command watchdog, and clamping that says what it clamped
// (as joshua_runtime.nodes.command_guard).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "drivers/calibration.hpp"
#include "joshua_rcl/node.hpp"

namespace joshua {

// Fires once when no goal arrived for `timeout_s`; the next goal re-arms it. Never fires before a first goal.
class CommandWatchdog {
 public:
  explicit CommandWatchdog(double timeout_s) : timeout_(std::chrono::duration<double>(timeout_s)) {}
  void feed(Clock::time_point now) {
    last_goal_ = now;
    fired_ = false;
  }
  // True once per silence longer than the timeout.
  bool expired(Clock::time_point now);

 private:
  std::chrono::duration<double> timeout_;
  std::optional<Clock::time_point> last_goal_;
  bool fired_ = false;
};

struct ClampedGoal {
  size_t index;  // in bus order
  std::string joint;
  double requested;  // rad
  double applied;    // rad, the nearest goal inside the calibrated range

  // "<joint> goal 2.000 rad clamped to 1.500 rad"
  std::string describe() const;
};

// Every goal (rad, NaN skipped) that falls outside its joint's calibrated range.
std::vector<ClampedGoal> clamped_goals(const std::vector<MotorCalibration>& calibrations,
                                       const std::vector<std::string>& joints, const std::vector<double>& goals);

}  // namespace joshua
