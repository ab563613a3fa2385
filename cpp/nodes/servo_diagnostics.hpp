// /diagnostics of the STS3215 nodes: one DiagnosticStatus per servo, every 1/diagnostics_rate_hz.
//
// Each publication costs one SYNC_READ of the telemetry span of every servo, run through the node's
// BusGuard between two control ticks. Readings are judged by assess() (STS3215 limits); a failed read
// makes every servo ERROR and counts as a read failure. The node adds its own findings: note() for one
// publication (a clamped goal), set_condition() for as long as it holds (a stopped actuator). Names,
// levels, messages and key/values are those of the Python node (joshua_runtime.nodes.servo_diagnostics).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "diagnostic_msgs/msg/diagnostic_array.hpp"
#include "drivers/sts3215_health.hpp"
#include "joshua_rcl/node.hpp"
#include "nodes/servo_bus.hpp"

namespace joshua {

class ServoDiagnostics {
 public:
  // Publishes at the diagnostics_rate_hz parameter (1 Hz when absent or 0); SettingsError when negative.
  ServoDiagnostics(Node& node, Sts3215Bus& bus, BusGuard& guard, const std::vector<std::string>& joint_names);

  // A finding about the servo at `index` (bus order), reported in the next publication only.
  void note(size_t index, Finding finding) { notes_.emplace_back(index, std::move(finding)); }
  // Raises a node counter reported with every servo (e.g. goals_clamped).
  void count(const std::string& name, int amount);
  // A finding reported for every servo until cleared with std::nullopt.
  void set_condition(std::optional<Finding> condition) { condition_ = std::move(condition); }

 private:
  void publish();
  diagnostic_msgs::msg::DiagnosticStatus status(size_t index, const ServoStatus* reading);

  const Node& node_;
  Sts3215Bus& bus_;
  BusGuard& guard_;
  std::vector<std::string> joint_names_;
  std::vector<int> read_failures_;
  std::vector<std::pair<std::string, int>> counters_;  // in the order they were first raised
  std::vector<std::pair<size_t, Finding>> notes_;
  std::optional<Finding> condition_;
  Publisher<diagnostic_msgs::msg::DiagnosticArray>* publisher_ = nullptr;
};

}  // namespace joshua
