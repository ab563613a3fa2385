// LIDAR_PUBLISHER: LDS-01 turns read from serial_port, published as LaserScan or PointCloud2 (the topic's
// message_type), one per turn, 5 Hz.
//
// The serial port is polled every POLL_PERIOD from the wait loop, so a stop signal is noticed at once.
// The node is ready once its first whole turn is published: a silent device is never ready.
// A silent or vanished device ends the node with exit code 3. Same messages as the Python node
// (joshua_runtime.nodes.lidar_publisher).
#include <cmath>
#include <memory>

#include "drivers/lds01.hpp"
#include "joshua_rcl/node.hpp"
#include "joshua_rcl/qos.hpp"
#include "sensor_msgs/msg/laser_scan.hpp"
#include "sensor_msgs/msg/point_cloud2.hpp"

namespace {

using namespace joshua;
using sensor_msgs::msg::LaserScan;
using sensor_msgs::msg::PointCloud2;
using sensor_msgs::msg::PointField;

constexpr double POLL_PERIOD_S = 0.01;
const char* const DEFAULT_FRAME_ID = "laser";
const char* const POINT_CLOUD2 = "sensor_msgs/msg/PointCloud2";
const char* const POINT_FIELDS[] = {"x", "y", "z", "intensity"};
constexpr uint32_t POINT_STEP = 4 * sizeof(float);

class LidarPublisher : public Application {
 public:
  bool ready_later() const override { return true; }

  void start(Node& node) override {
    node_ = &node;
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
    if (parameters.get_string("message_type") == POINT_CLOUD2) {
      clouds_ = &node.publisher<PointCloud2>(topic, qos);
    } else {
      scans_ = &node.publisher<LaserScan>(topic, qos);
    }
    node.every(POLL_PERIOD_S, [this] { publish_turns(); });
  }

  void close() override {
    if (lidar_) lidar_->close();
  }

 private:
  void publish_turns() {
    while (std::optional<LaserTurn> turn = lidar_->poll()) {
      if (clouds_) {
        clouds_->publish(point_cloud_message(scan_message(*turn)));
      } else {
        scans_->publish(scan_message(*turn));
      }
      node_->announce_ready("first scan published");
    }
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

  // The valid readings of a scan as float32 points x, y, z, intensity in the scan's frame, computed in
  // double from the scan's float32 fields as the Python node does (scan_geometry.scan_points).
  static PointCloud2 point_cloud_message(const LaserScan& scan) {
    PointCloud2 message;
    message.header = scan.header;
    message.height = 1;
    message.is_bigendian = false;
    message.point_step = POINT_STEP;
    message.is_dense = true;
    for (uint32_t i = 0; i < 4; ++i) {
      PointField field;
      field.name = POINT_FIELDS[i];
      field.offset = 4 * i;
      field.datatype = PointField::FLOAT32;
      field.count = 1;
      message.fields.push_back(field);
    }
    for (size_t k = 0; k < scan.ranges.size(); ++k) {
      const double range = scan.ranges[k];
      if (!std::isfinite(range) || range < double(scan.range_min) || range > double(scan.range_max)) continue;
      const double angle = double(scan.angle_min) + double(scan.angle_increment) * static_cast<double>(k);
      const float intensity = scan.intensities.size() == scan.ranges.size() ? scan.intensities[k] : 0.0f;
      const float point[4] = {static_cast<float>(range * std::cos(angle)), static_cast<float>(range * std::sin(angle)),
                              0.0f, intensity};
      const auto* bytes = reinterpret_cast<const uint8_t*>(point);  // little-endian, as is_bigendian says
      message.data.insert(message.data.end(), bytes, bytes + POINT_STEP);
      ++message.width;
    }
    message.row_step = POINT_STEP * message.width;
    return message;
  }

  Node* node_ = nullptr;
  std::unique_ptr<Lds01> lidar_;
  std::string frame_id_;
  Publisher<LaserScan>* scans_ = nullptr;
  Publisher<PointCloud2>* clouds_ = nullptr;
};

}  // namespace

int main(int argc, char** argv) {
  LidarPublisher application;
  joshua::run(argc, argv, "lidar_publisher", application);
}
