// LeRobot calibration files and the ticks <-> radians conversion they define (as the Python driver).
//
// radians = sign * (ticks - middle) * RADIANS_PER_TICK, middle = (range_min + range_max) / 2,
// sign = -1 for drive_mode 1; goals are clamped to [range_min, range_max], readings are not.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "drivers/sts3215_protocol.hpp"

namespace joshua {

struct MotorCalibration {
  int id = 0;
  int drive_mode = 0;
  int homing_offset = 0;
  int range_min = 0;
  int range_max = sts3215::MAX_TICK;

  double middle() const { return (range_min + range_max) / 2.0; }
  int sign() const { return drive_mode ? -1 : 1; }
  double to_radians(double ticks) const;
  double speed_to_radians(double ticks_per_s) const;
  // The raw position of a joint angle, in or out of the calibrated range.
  long unclamped_ticks(double radians) const;
  // The goal for a joint angle, clamped to the calibrated range.
  int to_ticks(double radians) const;
};

// Motor name -> calibration; SettingsError names the file and the problem.
std::map<std::string, MotorCalibration> load_calibration(const std::string& path);

// One calibration per servo in bus order, matched by joint name (the identity without a file).
std::vector<MotorCalibration> calibration_for_bus(const std::string& path, const std::vector<std::string>& joint_names,
                                                  const std::vector<int>& ids);

}  // namespace joshua
