// ACTUATOR_SUBSCRIBER: drives an STS3215 bus (e.g. a follower arm) from JointState commands or action chunks.
//
// On start the servos hold their present pose and torque goes on. Each command on topic_name is matched
// to joint_names by name (absent joints keep their goal) and sent at once in one SYNC_WRITE of goals
// clamped to the calibrated range; a clamped goal is logged (at most every CLAMP_LOG_INTERVAL) and noted
// on /diagnostics. With state_topic set, the bus's joint states are published there every 1/rate_hz.
// Torque goes off at exit unless keep_torque_on_exit is true.
//
// With message_type trajectory_msgs/msg/JointTrajectory, each chunk is followed by trajectory_follower.hpp:
// every 1/rate_hz its goal of that moment goes out like a command (clamped, feeding the watchdog); when the
// chunk is over its last point is held, and command_timeout_s counts from then.
//
// Preset commands (std_msgs/String) on `<topic_name>/preset`: torque_on, torque_off (the e-stop; torque
// stays off until torque_on) and pose names (home, rest, grip_open and the `preset` parameter's), which
// move like a goal. With command_timeout_s set, a silence that long stops the arm once
// (on_command_timeout: HOLD_POSITION holds the present position, RELEASE_TORQUE lets it go limp); the
// next goal or pose resumes it. Same behaviour as the Python node (joshua_runtime.nodes.actuator_subscriber).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "joshua_rcl/node.hpp"
#include "joshua_rcl/qos.hpp"
#include "nodes/command_guard.hpp"
#include "nodes/presets.hpp"
#include "nodes/servo_bus.hpp"
#include "nodes/servo_diagnostics.hpp"
#include "nodes/trajectory_follower.hpp"
#include "std_msgs/msg/string.hpp"

namespace {

using namespace joshua;
using sensor_msgs::msg::JointState;
using trajectory_msgs::msg::JointTrajectory;

constexpr std::chrono::seconds CLAMP_LOG_INTERVAL{1};
constexpr std::chrono::seconds DROP_LOG_INTERVAL{2};  // at most one "action chunk dropped" line per interval
const char* const JOINT_TRAJECTORY = "trajectory_msgs/msg/JointTrajectory";
const char* const RELEASE_TORQUE = "RELEASE_TORQUE";
const char* const PRESET_SUFFIX = "/preset";

// Where an actuator commanded on `topic` takes preset commands (joshua_core.servo_topics.preset_topic).
std::string preset_topic(std::string topic) {
  while (!topic.empty() && topic.back() == '/') topic.pop_back();
  return topic + PRESET_SUFFIX;
}

std::string stripped(const std::string& text) {
  const char* const space = " \t\n\r\f\v";
  const size_t first = text.find_first_not_of(space);
  return first == std::string::npos ? "" : text.substr(first, text.find_last_not_of(space) - first + 1);
}

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", seconds);
  return text;
}

class ActuatorSubscriber : public Application {
 public:
  void start(Node& node) override {
    node_ = &node;
    const Parameters& parameters = node.parameters();
    const double period = period_s(parameters);
    keep_torque_on_exit_ = parameters.get_bool("keep_torque_on_exit");
    const std::string topic = parameters.require_string("topic_name");
    const std::string state_topic = parameters.get_string("state_topic");
    const rmw_qos_profile_t qos = qos_from_parameters(parameters);
    frame_id_ = parameters.get_string("frame_id");
    command_timeout_s_ = parameters.get_double("command_timeout_s");
    release_on_timeout_ = parameters.get_string("on_command_timeout") == RELEASE_TORQUE;
    bus_ = bus_from_parameters(parameters, joint_names_);
    presets_ = std::make_unique<Presets>(parameters.get_string("preset"), joint_names_);
    bus_->open();
    bus_->enable_torque();
    guard_ = std::make_unique<BusGuard>(*bus_, node, [this] { restore_torque(); });
    diagnostics_ = std::make_unique<ServoDiagnostics>(node, *bus_, *guard_, joint_names_);
    if (parameters.get_string("message_type") == JOINT_TRAJECTORY) {
      node.subscribe<JointTrajectory>(topic, qos, [this](const JointTrajectory& message) { receive_chunk(message); });
      node.every(period, [this] { follow_chunk(); });
    } else {
      node.subscribe<JointState>(topic, qos, [this](const JointState& message) { command(message); });
    }
    node.subscribe<std_msgs::msg::String>(preset_topic(topic), fixed_qos(),
                                          [this](const std_msgs::msg::String& message) { preset(message.data); });
    if (command_timeout_s_ > 0) {
      watchdog_ = std::make_unique<CommandWatchdog>(command_timeout_s_);
      node.every(std::min(period, command_timeout_s_ / 4), [this] { watch(); });
    }
    if (!state_topic.empty()) {
      joint_states_ = &node.publisher<JointState>(state_topic, qos);
      node.every(period, [this] { publish_state(); });
    }
  }

  void close() override {
    if (!bus_) return;
    try {
      if (bus_->is_open() && !keep_torque_on_exit_) bus_->disable_torque();
    } catch (const DeviceError& error) {
      node_->warn(std::string("torque left on: ") + error.what());
    }
    bus_->close();
  }

 private:
  void command(const JointState& message) {
    const std::vector<double> goals = goals_from(message, joint_names_);
    if (goals.size() == joint_names_.size()) drive(goals);
  }

  void receive_chunk(const JointTrajectory& message) {
    const double arrival = ros_now_s();
    Chunk chunk;
    std::string dropped;
    if (chunk_from_trajectory(message, joint_names_, arrival, chunk, dropped)) dropped = chunks_.accept(chunk, arrival);
    const Clock::time_point now = Clock::now();
    if (!dropped.empty() && now >= next_drop_log_) {
      next_drop_log_ = now + DROP_LOG_INTERVAL;
      node_->warn("action chunk dropped: " + dropped);
    }
  }

  // Every control period: the goal of the chunk in force; once it is over, its last point once more.
  void follow_chunk() {
    const double now = ros_now_s();
    if (chunks_.executing(now)) {
      holding_ = false;
      drive(chunks_.goal(now));
    } else if (!holding_) {
      holding_ = true;
      drive(chunks_.goal(now));
    }
  }

  // Sends goal positions (rad, NaN: leave alone), clamped to the calibrated range, and feeds the watchdog.
  void drive(const std::vector<double>& goals) {
    if (watchdog_) {
      watchdog_->feed(Clock::now());
      if (released_by_watchdog_ && torque_on_) {
        node_->info("goal received: torque on again");
        guard_->call([&] { bus_->enable_torque(); });
      }
      released_by_watchdog_ = false;
      diagnostics_->set_condition(std::nullopt);
    }
    const std::vector<ClampedGoal> clamped = clamped_goals(bus_->calibration(), joint_names_, goals);
    guard_->call([&] { bus_->write_goals(goals); });
    if (!clamped.empty()) report(clamped);
  }

  void report(const std::vector<ClampedGoal>& clamped) {
    diagnostics_->count("goals_clamped", static_cast<int>(clamped.size()));
    std::string described;
    for (const ClampedGoal& goal : clamped) {
      diagnostics_->note(goal.index, {WARN, goal.describe()});
      described += (described.empty() ? "" : "; ") + goal.describe();
    }
    const Clock::time_point now = Clock::now();
    if (now >= next_clamp_log_) {
      next_clamp_log_ = now + CLAMP_LOG_INTERVAL;
      node_->warn("outside the calibrated range: " + described);
    }
  }

  void preset(const std::string& data) {
    const std::string name = stripped(data);
    if (name == TORQUE_ON || name == TORQUE_OFF) {
      torque_on_ = name == TORQUE_ON;
      released_by_watchdog_ = false;
      node_->info("preset " + name);
      guard_->call([&] { torque_on_ ? bus_->enable_torque() : bus_->disable_torque(); });
      return;
    }
    std::vector<double> goals;
    if (!presets_->goals(name, goals)) {
      node_->warn("unknown preset " + python_repr(name) + ": known are " + presets_->known());
      return;
    }
    if (std::any_of(goals.begin(), goals.end(), [](double goal) { return !std::isnan(goal); })) drive(goals);
  }

  void watch() {
    if (!watchdog_->expired(Clock::now())) return;
    if (!torque_on_) return;  // torque is already off (torque_off preset): nothing to stop
    const std::string silence = "no goal for " + seconds_text(command_timeout_s_) + " s: ";
    if (release_on_timeout_) {
      node_->warn(silence + "torque off until the next goal");
      released_by_watchdog_ = true;
      guard_->call([&] { bus_->disable_torque(); });
      diagnostics_->set_condition(Finding{WARN, silence + "torque released"});
    } else {
      node_->warn(silence + "holding the present position");
      guard_->call([&] { bus_->hold_present_pose(); });
      diagnostics_->set_condition(Finding{WARN, silence + "holding position"});
    }
  }

  // After a reconnect: torque as it was (a power-cycled servo starts limp).
  void restore_torque() {
    if (torque_on_ && !released_by_watchdog_) bus_->enable_torque();
  }

  void publish_state() {
    std::vector<JointReading> readings;
    if (guard_->call([&] { readings = bus_->read_state(); })) {
      joint_states_->publish(joint_state(joint_names_, readings, frame_id_));
    }
  }

  Node* node_ = nullptr;
  std::unique_ptr<Sts3215Bus> bus_;
  std::unique_ptr<BusGuard> guard_;
  std::unique_ptr<ServoDiagnostics> diagnostics_;
  std::unique_ptr<Presets> presets_;
  std::unique_ptr<CommandWatchdog> watchdog_;
  std::vector<std::string> joint_names_;
  std::string frame_id_;
  bool keep_torque_on_exit_ = false;
  double command_timeout_s_ = 0;
  bool release_on_timeout_ = false;
  bool torque_on_ = true;  // off after a torque_off preset until torque_on
  bool released_by_watchdog_ = false;
  Clock::time_point next_clamp_log_;
  TrajectoryFollower chunks_;
  bool holding_ = true;  // the last chunk is over (or none came yet)
  Clock::time_point next_drop_log_;
  Publisher<JointState>* joint_states_ = nullptr;
};

}  // namespace

int main(int argc, char** argv) {
  ActuatorSubscriber application;
  joshua::run(argc, argv, "actuator_subscriber", application);
}
