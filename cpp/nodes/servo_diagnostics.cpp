// Building and publishing the DiagnosticArray of a servo bus.
#include "nodes/servo_diagnostics.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "joshua_rcl/qos.hpp"

namespace joshua {
namespace {

using diagnostic_msgs::msg::DiagnosticArray;
using diagnostic_msgs::msg::DiagnosticStatus;
using diagnostic_msgs::msg::KeyValue;

const char* const DIAGNOSTICS_TOPIC = "/diagnostics";
constexpr double DEFAULT_RATE_HZ = 1.0;

// A value in 0.1 steps as Python's str() writes it ("12.1", "0.0").
std::string tenths(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", value);
  return text;
}

std::string joined(const std::vector<std::string>& parts, const char* separator) {
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : separator) + part;
  return text;
}

KeyValue key_value(const std::string& key, const std::string& value) {
  KeyValue pair;
  pair.key = key;
  pair.value = value;
  return pair;
}

}  // namespace

ServoDiagnostics::ServoDiagnostics(Node& node, Sts3215Bus& bus, BusGuard& guard,
                                   const std::vector<std::string>& joint_names)
    : node_(node), bus_(bus), guard_(guard), joint_names_(joint_names), read_failures_(joint_names.size(), 0) {
  double rate = node.parameters().get_double("diagnostics_rate_hz");
  if (rate == 0) rate = DEFAULT_RATE_HZ;
  if (!(rate > 0)) {
    std::ostringstream text;
    text << "diagnostics_rate_hz must be positive, got " << rate;
    throw SettingsError(text.str());
  }
  publisher_ = &node.publisher<DiagnosticArray>(DIAGNOSTICS_TOPIC, fixed_qos());
  node.every(1.0 / rate, [this] { publish(); });
}

void ServoDiagnostics::count(const std::string& name, int amount) {
  auto found = std::find_if(counters_.begin(), counters_.end(), [&](const auto& counter) { return counter.first == name; });
  if (found == counters_.end()) {
    counters_.emplace_back(name, amount);
  } else {
    found->second += amount;
  }
}

void ServoDiagnostics::publish() {
  std::vector<ServoStatus> readings;
  const bool read = guard_.call([&] { readings = read_status(bus_); });
  DiagnosticArray message;
  message.header.stamp = wall_clock_stamp();
  for (size_t index = 0; index < joint_names_.size(); ++index) {
    message.status.push_back(status(index, read ? &readings[index] : nullptr));
  }
  notes_.clear();
  publisher_->publish(message);
}

DiagnosticStatus ServoDiagnostics::status(size_t index, const ServoStatus* reading) {
  const int servo_id = bus_.ids()[index];
  std::vector<Finding> findings;
  if (reading == nullptr) {
    ++read_failures_[index];
    const std::string reason = guard_.last_error().empty() ? "bus unavailable" : guard_.last_error();
    findings.push_back(read_failure(servo_id, reason));
  } else {
    findings = assess(*reading);
  }
  for (const auto& [servo, finding] : notes_) {
    if (servo == index) findings.push_back(finding);
  }
  if (condition_) findings.push_back(*condition_);
  std::stable_sort(findings.begin(), findings.end(), [](const Finding& a, const Finding& b) { return a.level > b.level; });

  DiagnosticStatus status;
  status.level = worst(findings);
  status.name = node_.name() + ": " + joint_names_[index];
  status.hardware_id = bus_.port() + " id " + std::to_string(servo_id);
  std::vector<std::string> messages;
  for (const Finding& finding : findings) messages.push_back(finding.message);
  status.message = messages.empty() ? "OK" : joined(messages, "; ");
  status.values.push_back(key_value("servo_id", std::to_string(servo_id)));
  status.values.push_back(key_value("read_failures", std::to_string(read_failures_[index])));
  for (const auto& [name, value] : counters_) status.values.push_back(key_value(name, std::to_string(value)));
  if (reading != nullptr) {
    const std::vector<std::string> errors = reading->errors();
    status.values.push_back(key_value("temperature_c", std::to_string(reading->temperature_c)));
    status.values.push_back(key_value("voltage_v", tenths(reading->voltage_v)));
    status.values.push_back(key_value("load_percent", tenths(reading->load_percent)));
    status.values.push_back(key_value("position_ticks", std::to_string(reading->position)));
    status.values.push_back(key_value("errors", errors.empty() ? "none" : joined(errors, ", ")));
  }
  return status;
}

}  // namespace joshua
