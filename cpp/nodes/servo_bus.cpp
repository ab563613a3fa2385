// Bus construction from parameters, JointState conversion and the reconnecting BusGuard.
#include "nodes/servo_bus.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace joshua {
namespace {

constexpr std::chrono::milliseconds DEVICE_LOST_GRACE{3000};
constexpr std::chrono::milliseconds RECONNECT_INTERVAL{250};
constexpr std::chrono::milliseconds LOG_INTERVAL{1000};
constexpr int64_t DEFAULT_BAUD_RATE = 1000000;

}  // namespace

std::unique_ptr<Sts3215Bus> bus_from_parameters(const Parameters& parameters, std::vector<std::string>& joint_names) {
  const std::vector<int64_t> raw_ids = parameters.get_int_array("device_ids");
  if (raw_ids.empty()) throw SettingsError("device_ids is empty");
  std::vector<int> ids;
  for (int64_t id : raw_ids) {
    if (id < 0 || id > 253) throw SettingsError("device id " + std::to_string(id) + " is out of range 0-253");
    ids.push_back(static_cast<int>(id));
  }
  joint_names = parameters.get_string_array("joint_names");
  if (joint_names.empty()) {
    for (int id : ids) joint_names.push_back("joint_" + std::to_string(id));
  }
  if (joint_names.size() != ids.size()) {
    throw SettingsError(std::to_string(joint_names.size()) + " joint_names for " + std::to_string(ids.size()) +
                        " device_ids");
  }
  const std::string calibration_file = parameters.get_string("calibration_file");
  const std::string port = parameters.require_string("serial_port");
  int64_t baud_rate = parameters.get_int("baud_rate", DEFAULT_BAUD_RATE);
  if (baud_rate <= 0) baud_rate = DEFAULT_BAUD_RATE;
  return std::make_unique<Sts3215Bus>(port, static_cast<int>(baud_rate), ids,
                                      calibration_for_bus(calibration_file, joint_names, ids), !calibration_file.empty());
}

double period_s(const Parameters& parameters) {
  const double rate = parameters.get_double("rate_hz");
  if (!(rate > 0)) {
    std::ostringstream text;
    text << "rate_hz must be positive, got " << rate;
    throw SettingsError(text.str());
  }
  return 1.0 / rate;
}

builtin_interfaces::msg::Time wall_clock_stamp() {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  const int64_t nanoseconds = std::chrono::duration_cast<std::chrono::nanoseconds>(now).count();
  builtin_interfaces::msg::Time stamp;
  stamp.sec = static_cast<int32_t>(nanoseconds / 1000000000);
  stamp.nanosec = static_cast<uint32_t>(nanoseconds % 1000000000);
  return stamp;
}

sensor_msgs::msg::JointState joint_state(const std::vector<std::string>& joint_names,
                                         const std::vector<JointReading>& readings, const std::string& frame_id) {
  sensor_msgs::msg::JointState message;
  message.header.stamp = wall_clock_stamp();
  message.header.frame_id = frame_id;
  message.name = joint_names;
  for (const JointReading& reading : readings) {
    message.position.push_back(reading.position);
    message.velocity.push_back(reading.velocity);
    message.effort.push_back(reading.effort);
  }
  return message;
}

std::vector<double> goals_from(const sensor_msgs::msg::JointState& message,
                               const std::vector<std::string>& joint_names) {
  if (message.position.empty()) return {};
  const double absent = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> goals(joint_names.size(), absent);
  if (message.name.empty()) {
    if (message.position.size() == joint_names.size()) goals = message.position;
    return goals;
  }
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < message.name.size(); ++i) index.emplace(message.name[i], i);
  for (size_t j = 0; j < joint_names.size(); ++j) {
    auto found = index.find(joint_names[j]);
    if (found != index.end() && found->second < message.position.size()) goals[j] = message.position[found->second];
  }
  return goals;
}

BusGuard::BusGuard(Sts3215Bus& bus, const Node& node, std::function<void()> on_reconnect)
    : bus_(bus), node_(node), on_reconnect_(std::move(on_reconnect)), connections_(bus.connections()) {}

bool BusGuard::call(const std::function<void()>& operation) {
  const Clock::time_point now = Clock::now();
  if (failing_ && !bus_.is_open() && now < next_attempt_) {
    check_grace(now);
    return false;
  }
  try {
    operation();
  } catch (const DeviceError& error) {
    failed(now, error);
    return false;
  }
  if (bus_.connections() != connections_) {
    connections_ = bus_.connections();
    node_.info(bus_.port() + ": reconnected");
    if (on_reconnect_) on_reconnect_();
  }
  failing_ = false;
  return true;
}

void BusGuard::failed(Clock::time_point now, const DeviceError& error) {
  if (!failing_) {
    failing_ = true;
    failing_since_ = now;
  }
  last_error_ = error.what();
  next_attempt_ = now + RECONNECT_INTERVAL;
  if (now >= next_log_) {
    next_log_ = now + LOG_INTERVAL;
    node_.warn(last_error_);
  }
  check_grace(now);
}

void BusGuard::check_grace(Clock::time_point now) {
  if (now - failing_since_ >= DEVICE_LOST_GRACE) {
    const auto grace_s = std::chrono::duration_cast<std::chrono::seconds>(DEVICE_LOST_GRACE).count();
    throw DeviceError(bus_.port() + ": bus failing for " + std::to_string(grace_s) + " s: " + last_error_);
  }
}

}  // namespace joshua
