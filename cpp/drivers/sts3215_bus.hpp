// One serial bus of STS3215 servos (ids in joint order): state reads, goal writes, torque, calibration.
//
// Mirrors the Python Sts3215Driver and SerialTransport: a transaction retries a missing or corrupt
// reply up to MAX_RETRIES times; open() pings every servo, checks its model number and writes the
// calibration file's Homing_Offset and limits into servos that differ; a vanished port closes the bus
// and raises DeviceError, and the next call reopens it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "drivers/calibration.hpp"
#include "drivers/serial_port.hpp"
#include "drivers/sts3215_protocol.hpp"

namespace joshua {

struct JointReading {
  double position;  // rad
  double velocity;  // rad/s
  double effort;    // signed fraction of the maximum torque
};

class Sts3215Bus {
 public:
  Sts3215Bus(const std::string& port, int baud_rate, std::vector<int> ids, std::vector<MotorCalibration> calibration,
             bool calibrated);

  // DeviceError names the missing or wrong servos. Reconnecting stops at the first missing one.
  void open(bool list_every_missing = true);
  void close() { port_.close(); }
  bool is_open() const { return port_.is_open(); }
  const std::string& port() const { return port_.path(); }
  int connections() const { return connections_; }

  // One SYNC_READ of position, velocity and load, in bus order.
  std::vector<JointReading> read_state();
  // One SYNC_WRITE of Goal_Position (rad, clamped to the calibrated range; NaN leaves a joint alone).
  void write_goals(const std::vector<double>& radians);
  // Goal_Position = Present_Position on every servo (torque unchanged).
  void hold_present_pose();
  // Holds the present pose, then switches torque on.
  void enable_torque();
  void disable_torque();
  // One SYNC_READ of `size` raw bytes from `address` of every servo, in bus order.
  std::vector<sts3215::Bytes> read_blocks(uint8_t address, uint8_t size);
  const std::vector<MotorCalibration>& calibration() const { return calibration_; }
  const std::vector<uint8_t>& ids() const { return ids_; }

 private:
  struct Expected {
    uint8_t servo_id;
    size_t param_bytes;
  };

  void ensure_open();
  void check_servos(bool list_every_missing);
  void store_calibration();
  int read_register(uint8_t servo_id, const sts3215::Register& reg);
  void write_register(uint8_t servo_id, const sts3215::Register& reg, int value);
  std::vector<sts3215::Packet> transact(const sts3215::Bytes& packet, const std::vector<Expected>& expected);
  void send(const sts3215::Bytes& packet) { port_.write_all(packet.data(), packet.size()); }
  // Waits for one status packet: 0 when `packet` holds it, else why not (timeout, corrupt or garbled reply).
  int receive(const Expected& item, sts3215::Packet& packet);
  sts3215::Bytes read_block(uint8_t servo_id, uint8_t address, uint8_t size);
  std::vector<sts3215::Packet> sync_read_block(uint8_t address, uint8_t size);
  void sync_write(const sts3215::Register& reg, const std::vector<std::pair<uint8_t, int>>& values);

  SerialPort port_;
  std::vector<uint8_t> ids_;
  std::vector<MotorCalibration> calibration_;
  bool calibrated_;
  std::vector<bool> acknowledges_;  // per servo: answers WRITE with a status packet
  sts3215::PacketParser parser_;
  int connections_ = 0;
};

}  // namespace joshua
