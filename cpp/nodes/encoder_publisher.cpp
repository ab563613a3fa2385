// ENCODER_PUBLISHER: the joint states of an STS3215 bus (e.g. a leader arm) as JointState, every 1/rate_hz.
//
// The arm is moved by hand, so torque is switched off when the bus opens (and again after a reconnect).
// Servo health goes to /diagnostics every 1/diagnostics_rate_hz (servo_diagnostics).
// Same parameters, messages and exit codes as the Python node (joshua_runtime.nodes.encoder_publisher).
#include <memory>

#include "joshua_rcl/node.hpp"
#include "joshua_rcl/qos.hpp"
#include "nodes/servo_bus.hpp"
#include "nodes/servo_diagnostics.hpp"

namespace {

using namespace joshua;

class EncoderPublisher : public Application {
 public:
  void start(Node& node) override {
    const Parameters& parameters = node.parameters();
    const double period = period_s(parameters);
    const std::string topic = parameters.require_string("topic_name");
    const rmw_qos_profile_t qos = qos_from_parameters(parameters);
    frame_id_ = parameters.get_string("frame_id");
    bus_ = bus_from_parameters(parameters, joint_names_);
    bus_->open();
    bus_->disable_torque();
    guard_ = std::make_unique<BusGuard>(*bus_, node, [this] { bus_->disable_torque(); });
    joint_states_ = &node.publisher<sensor_msgs::msg::JointState>(topic, qos);
    node.every(period, [this] { publish(); });
    diagnostics_ = std::make_unique<ServoDiagnostics>(node, *bus_, *guard_, joint_names_);
  }

  void close() override {
    if (bus_) bus_->close();
  }

 private:
  void publish() {
    std::vector<JointReading> readings;
    if (guard_->call([&] { readings = bus_->read_state(); })) {
      joint_states_->publish(joint_state(joint_names_, readings, frame_id_));
    }
  }

  std::unique_ptr<Sts3215Bus> bus_;
  std::unique_ptr<BusGuard> guard_;
  std::unique_ptr<ServoDiagnostics> diagnostics_;
  std::vector<std::string> joint_names_;
  std::string frame_id_;
  Publisher<sensor_msgs::msg::JointState>* joint_states_ = nullptr;
};

}  // namespace

int main(int argc, char** argv) {
  EncoderPublisher application;
  joshua::run(argc, argv, "encoder_publisher", application);
}
