// The command watchdog's clock and the clamping report.
#include "nodes/command_guard.hpp"

#include <cmath>
#include <cstdio>

namespace joshua {

bool CommandWatchdog::expired(Clock::time_point now) {
  if (!last_goal_ || fired_ || now - *last_goal_ < timeout_) return false;
  fired_ = true;
  return true;
}

std::string ClampedGoal::describe() const {
  char numbers[96];
  std::snprintf(numbers, sizeof numbers, " goal %.3f rad clamped to %.3f rad", requested, applied);
  return joint + numbers;
}

std::vector<ClampedGoal> clamped_goals(const std::vector<MotorCalibration>& calibrations,
                                       const std::vector<std::string>& joints, const std::vector<double>& goals) {
  std::vector<ClampedGoal> clamped;
  for (size_t i = 0; i < calibrations.size() && i < joints.size() && i < goals.size(); ++i) {
    if (std::isnan(goals[i])) continue;
    const MotorCalibration& motor = calibrations[i];
    const int ticks = motor.to_ticks(goals[i]);
    if (ticks != motor.unclamped_ticks(goals[i])) clamped.push_back({i, joints[i], goals[i], motor.to_radians(ticks)});
  }
  return clamped;
}

}  // namespace joshua
