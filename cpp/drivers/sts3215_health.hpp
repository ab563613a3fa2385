// One telemetry reading per servo and its judgement against the STS3215 limits (as drivers/sts3215_health.py).
//
// Levels are diagnostic_msgs/DiagnosticStatus levels (OK 0, WARN 1, ERROR 2). A reading within a
// margin of a factory protection limit warns before the servo protects itself.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "drivers/sts3215_bus.hpp"

namespace joshua {

enum Level : uint8_t { OK = 0, WARN = 1, ERROR = 2 };

struct ServoStatus {
  int id;
  int position;         // ticks
  int speed;            // ticks/s
  double load_percent;  // signed, of the maximum torque, 0.1 % steps
  double voltage_v;     // 0.1 V steps
  int temperature_c;
  int error_bits;
  bool moving;
  double current_ma;

  // Names of the set error bits, in bit order.
  std::vector<std::string> errors() const;
};

struct Finding {
  Level level;
  std::string message;
};

// Telemetry of every servo of the bus, in bus order, with one SYNC_READ.
std::vector<ServoStatus> read_status(Sts3215Bus& bus);

// Every concern about one reading, worst first; empty means OK.
std::vector<Finding> assess(const ServoStatus& status);

// The worst level of `findings` (OK when there is none).
Level worst(const std::vector<Finding>& findings);

// The finding for a servo that could not be read at all.
Finding read_failure(int servo_id, const std::string& reason);

}  // namespace joshua
