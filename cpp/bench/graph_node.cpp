// The C++ peer of bench/discovery.py: a node as small as the C++ nodes make them, on the same joshua_rcl
// (context, node, one sensor_msgs/JointState publisher at rate_hz, the wait loop, READY=1), with no device.
// What a Python MOCK_ENCODER_PUBLISHER does on the graph, so that N of them started at once show what DDS
// discovery on this machine costs without Python:
//
//     build/bench/graph_node --ros-args -r __node:=disc00 -p topic_name:=/disc00/joints -p rate_hz:=5
//
// Built by `make -C cpp bench`; not a node type, and in no image or bundle.
#include "joshua_rcl/node.hpp"
#include "joshua_rcl/qos.hpp"
#include "sensor_msgs/msg/joint_state.hpp"

namespace {

using namespace joshua;
using sensor_msgs::msg::JointState;

constexpr double DEFAULT_RATE_HZ = 5.0;

class GraphNode : public Application {
 public:
  void start(Node& node) override {
    const std::string topic = node.parameters().require_string("topic_name");
    const double rate_hz = node.parameters().get_double("rate_hz", DEFAULT_RATE_HZ);
    if (rate_hz <= 0) throw SettingsError("rate_hz must be positive");
    Publisher<JointState>& joints = node.publisher<JointState>(topic, fixed_qos());
    node.every(1.0 / rate_hz, [&joints] { joints.publish(JointState()); });
  }
};

}  // namespace

int main(int argc, char** argv) {
  GraphNode application;
  joshua::run(argc, argv, "graph_node", application);
}
