// LIDAR_PUBLISHER: LDS-01 turns read from serial_port, published as LaserScan (one per turn, 5 Hz).
//
// The serial port is polled every POLL_PERIOD from the wait loop, so a stop signal is noticed at once.
// A silent or vanished device ends the node with exit code 3. Same messages as the Python node
// (joshua_runtime.nodes.lidar_publisher).
#include <cmath>
#include <memory>

#include "drivers/lds01.hpp"
#include "joshua_rcl/node.hpp"
#include "joshua_rcl/qos.hpp"
#include "sensor_msgs/msg/laser_scan.hpp"

namespace {

using namespace joshua;
using sensor_msgs::msg::LaserScan;

constexpr double POLL_PERIOD_S = 0.01;
const char* const DEFAULT_FRAME_ID = "laser";

class LidarPublisher : public Application {
 public:
  void start(Node& node) override {
    const Parameters& parameters = node.parameters();
    const std::string topic = parameters.get_string("topic_name");
    if (topic.empty()) throw SettingsError("LIDAR_PUBLISHER needs a topic_name");
    const std::string port = parameters.get_string("serial_port");
    if (port.empty()) throw SettingsError("LIDAR_PUBLISHER needs a serial_port");
    int64_t baud_rate = parameters.get_int("baud_rate", Lds01::DEFAULT_BAUD_RATE);
    if (baud_rate <= 0) baud_rate = Lds01::DEFAULT_BAUD_RATE;
    frame_id_ = parameters.get_string("frame_id");
    if (frame_id_.empty()) frame_id_ = DEFAULT_FRAME_ID;
    const rmw_qos_profile_t qos = qos_from_parameters(parameters);
    lidar_ = std::make_unique<Lds01>(port, static_cast<int>(baud_rate));
    lidar_->open();
    scans_ = &node.publisher<LaserScan>(topic, qos);
    node.every(POLL_PERIOD_S, [this] { publish_turns(); });
  }

  void close() override {
    if (lidar_) lidar_->close();
  }

 private:
  void publish_turns() {
    while (std::optional<LaserTurn> turn = lidar_->poll()) scans_->publish(scan_message(*turn));
  }

  LaserScan scan_message(const LaserTurn& turn) const {
    const double increment = 2.0 * M_PI / Lds01::READINGS_PER_TURN;
    LaserScan message;
    message.header.stamp.sec = static_cast<int32_t>(turn.first_reading_ns / 1000000000);
    message.header.stamp.nanosec = static_cast<uint32_t>(turn.first_reading_ns % 1000000000);
    message.header.frame_id = frame_id_;
    message.angle_min = 0.0f;
    message.angle_max = static_cast<float>(2.0 * M_PI - increment);
    message.angle_increment = static_cast<float>(increment);
    message.time_increment = static_cast<float>(turn.time_increment_s);
    message.scan_time = static_cast<float>(turn.time_increment_s * Lds01::READINGS_PER_TURN);
    message.range_min = static_cast<float>(Lds01::RANGE_MIN_M);
    message.range_max = static_cast<float>(Lds01::RANGE_MAX_M);
    message.ranges = turn.ranges;
    message.intensities = turn.intensities;
    return message;
  }

  std::unique_ptr<Lds01> lidar_;
  std::string frame_id_;
  Publisher<LaserScan>* scans_ = nullptr;
};

}  // namespace

int main(int argc, char** argv) {
  LidarPublisher application;
  joshua::run(argc, argv, "lidar_publisher", application);
}
