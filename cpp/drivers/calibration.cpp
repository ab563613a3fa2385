// Reading LeRobot calibration JSON with nlohmann::json, with the Python driver's error messages.
#include "drivers/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "joshua_rcl/errors.hpp"

namespace joshua {
namespace {

constexpr double RADIANS_PER_TICK = 2 * M_PI / sts3215::MAX_TICK;
const char* const FIELDS[] = {"id", "drive_mode", "homing_offset", "range_min", "range_max"};
const char* const FIELD_LIST = "id, drive_mode, homing_offset, range_min, range_max";

// Python's round(): halves to even.
long round_half_even(double value) { return std::lrint(value); }

}  // namespace

double MotorCalibration::to_radians(double ticks) const { return sign() * (ticks - middle()) * RADIANS_PER_TICK; }

double MotorCalibration::speed_to_radians(double ticks_per_s) const { return sign() * ticks_per_s * RADIANS_PER_TICK; }

long MotorCalibration::unclamped_ticks(double radians) const {
  return round_half_even(middle() + sign() * radians / RADIANS_PER_TICK);
}

int MotorCalibration::to_ticks(double radians) const {
  const long ticks = unclamped_ticks(radians);
  return static_cast<int>(std::min<long>(std::max<long>(ticks, range_min), range_max));
}

std::map<std::string, MotorCalibration> load_calibration(const std::string& path) {
  std::ifstream stream(path);
  if (!stream) throw SettingsError("calibration file " + path + " not found");
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(stream);
  } catch (const nlohmann::json::exception& error) {
    throw SettingsError("calibration file " + path + " is unreadable: " + error.what());
  }
  if (!document.is_object()) throw SettingsError("calibration file " + path + ": expected an object of motor names");
  std::map<std::string, MotorCalibration> motors;
  for (const auto& [name, entry] : document.items()) {
    for (const char* field : FIELDS) {
      if (!entry.is_object() || !entry.contains(field) || !entry[field].is_number_integer()) {
        throw SettingsError("calibration file " + path + ": motor '" + name + "' needs integer fields " + FIELD_LIST);
      }
    }
    MotorCalibration motor{entry["id"].get<int>(), entry["drive_mode"].get<int>(), entry["homing_offset"].get<int>(),
                           entry["range_min"].get<int>(), entry["range_max"].get<int>()};
    if (motor.range_min >= motor.range_max) {
      throw SettingsError("calibration file " + path + ": motor '" + name + "' has range_min >= range_max");
    }
    motors[name] = motor;
  }
  return motors;
}

std::vector<MotorCalibration> calibration_for_bus(const std::string& path, const std::vector<std::string>& joint_names,
                                                  const std::vector<int>& ids) {
  std::vector<MotorCalibration> calibrations;
  if (path.empty()) {
    for (int id : ids) calibrations.push_back(MotorCalibration{id});
    return calibrations;
  }
  const auto motors = load_calibration(path);
  std::string missing;
  for (const std::string& name : joint_names) {
    if (motors.count(name) == 0) missing += (missing.empty() ? "" : ", ") + name;
  }
  if (!missing.empty()) throw SettingsError("calibration file " + path + " has no entry for " + missing);
  for (size_t i = 0; i < joint_names.size(); ++i) {
    const MotorCalibration& motor = motors.at(joint_names[i]);
    if (motor.id != ids[i]) {
      throw SettingsError("calibration file " + path + ": " + joint_names[i] + " has id " + std::to_string(motor.id) +
                          ", the bus uses id " + std::to_string(ids[i]));
    }
    calibrations.push_back(motor);
  }
  return calibrations;
}

}  // namespace joshua
