// Decoding the telemetry span and judging it, with the Python node's limits and messages.
#include "drivers/sts3215_health.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace joshua {
namespace {

using namespace sts3215;

constexpr double VOLTS_PER_UNIT = 0.1;
constexpr double LOAD_PERCENT_PER_UNIT = 0.1;
constexpr double MILLIAMPS_PER_UNIT = 6.5;
constexpr int TEMPERATURE_WARN_MARGIN_C = 10;
constexpr double VOLTAGE_WARN_MARGIN_V = 0.5;
// The limits as the Python side computes them (register default times unit), so comparisons agree bit for bit.
const double MIN_VOLTAGE_V = DEFAULT_MIN_VOLTAGE * VOLTS_PER_UNIT;
const double MAX_VOLTAGE_V = DEFAULT_MAX_VOLTAGE * VOLTS_PER_UNIT;
const double MAX_LOAD_PERCENT = DEFAULT_MAX_TORQUE * LOAD_PERCENT_PER_UNIT;

// One register of the telemetry span.
int field(const Bytes& block, const Register& reg) {
  return decode_value(reg, block.data() + (reg.address - TELEMETRY_ADDRESS));
}

template <class... Args>
std::string format(const char* pattern, Args... args) {
  char text[160];
  std::snprintf(text, sizeof text, pattern, args...);
  return text;
}

}  // namespace

std::vector<std::string> ServoStatus::errors() const {
  std::vector<std::string> names;
  for (const auto& [bit, name] : ERROR_NAMES) {
    if (error_bits & bit) names.emplace_back(name);
  }
  return names;
}

std::vector<ServoStatus> read_status(Sts3215Bus& bus) {
  const std::vector<Bytes> blocks = bus.read_blocks(TELEMETRY_ADDRESS, TELEMETRY_SIZE);
  std::vector<ServoStatus> statuses;
  for (size_t i = 0; i < blocks.size(); ++i) {
    const Bytes& block = blocks[i];
    // n / 10.0 is the double Python's round(n * 0.1, 1) gives.
    statuses.push_back({bus.ids()[i], field(block, PRESENT_POSITION), field(block, PRESENT_VELOCITY),
                        field(block, PRESENT_LOAD) / 10.0, field(block, PRESENT_VOLTAGE) / 10.0,
                        field(block, PRESENT_TEMPERATURE), field(block, STATUS), field(block, MOVING) != 0,
                        field(block, PRESENT_CURRENT) * MILLIAMPS_PER_UNIT});
  }
  return statuses;
}

std::vector<Finding> assess(const ServoStatus& status) {
  std::vector<Finding> findings;
  for (const std::string& name : status.errors()) findings.push_back({ERROR, "servo reports " + name});
  const int temperature = status.temperature_c;
  if (temperature >= DEFAULT_MAX_TEMPERATURE_C) {
    findings.push_back({ERROR, format("temperature %d C at or above %d C", temperature, DEFAULT_MAX_TEMPERATURE_C)});
  } else if (temperature >= DEFAULT_MAX_TEMPERATURE_C - TEMPERATURE_WARN_MARGIN_C) {
    findings.push_back({WARN, format("temperature %d C near %d C", temperature, DEFAULT_MAX_TEMPERATURE_C)});
  }
  const double volts = status.voltage_v;
  if (!(MIN_VOLTAGE_V <= volts && volts <= MAX_VOLTAGE_V)) {
    findings.push_back({ERROR, format("voltage %.1f V outside %.1f-%.1f V", volts, MIN_VOLTAGE_V, MAX_VOLTAGE_V)});
  } else if (std::min(volts - MIN_VOLTAGE_V, MAX_VOLTAGE_V - volts) < VOLTAGE_WARN_MARGIN_V) {
    findings.push_back({WARN, format("voltage %.1f V near its limit", volts)});
  }
  const double load = std::fabs(status.load_percent);
  if (load >= MAX_LOAD_PERCENT) {
    findings.push_back({ERROR, format("load %.0f %% at maximum torque", load)});
  } else if (load >= DEFAULT_OVERLOAD_TORQUE) {
    findings.push_back({WARN, format("load %.0f %% above %d %%", load, DEFAULT_OVERLOAD_TORQUE)});
  }
  std::stable_sort(findings.begin(), findings.end(), [](const Finding& a, const Finding& b) { return a.level > b.level; });
  return findings;
}

Level worst(const std::vector<Finding>& findings) {
  Level level = OK;
  for (const Finding& finding : findings) level = std::max(level, finding.level);
  return level;
}

Finding read_failure(int servo_id, const std::string& reason) {
  return {ERROR, "servo id " + std::to_string(servo_id) + " unreadable: " + reason};
}

}  // namespace joshua
