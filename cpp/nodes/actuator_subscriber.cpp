// ACTUATOR_SUBSCRIBER: drives an STS3215 bus (e.g. a follower arm) from JointState commands.
//
// On start the servos hold their present pose and torque goes on. Each command on topic_name is matched
// to joint_names by name (absent joints keep their goal) and sent at once in one SYNC_WRITE of goals
// clamped to the calibrated range. With state_topic set, the bus's joint states are published there
// every 1/rate_hz. Torque goes off at exit unless keep_torque_on_exit is true. Same behaviour as the
// Python node (joshua_runtime.nodes.actuator_subscriber).
#include <memory>

#include "joshua_rcl/node.hpp"
#include "joshua_rcl/qos.hpp"
#include "nodes/servo_bus.hpp"

namespace {

using namespace joshua;
using sensor_msgs::msg::JointState;

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
    bus_ = bus_from_parameters(parameters, joint_names_);
    bus_->open();
    bus_->enable_torque();
    guard_ = std::make_unique<BusGuard>(*bus_, node, [this] { bus_->enable_torque(); });
    node.subscribe<JointState>(topic, qos, [this](const JointState& message) { command(message); });
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
    if (goals.size() == joint_names_.size()) guard_->call([&] { bus_->write_goals(goals); });
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
  std::vector<std::string> joint_names_;
  std::string frame_id_;
  bool keep_torque_on_exit_ = false;
  Publisher<JointState>* joint_states_ = nullptr;
};

}  // namespace

int main(int argc, char** argv) {
  ActuatorSubscriber application;
  joshua::run(argc, argv, "actuator_subscriber", application);
}
