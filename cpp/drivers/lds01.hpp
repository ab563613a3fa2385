// LDS-01 (HLS-LFCD2) lidar over a SerialPort: complete turns assembled as the Python driver does.
//
// Sync on `FA A0`, take that packet and the 59 that follow (2,520 bytes), and place reading n = 6k + j
// of packet k at scan index 359 - n. A packet is used when byte 1 is 0xA0 + k and its speed is non-zero;
// the readings of a skipped packet stay 0. A turn without one good packet is dropped.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "drivers/serial_port.hpp"

namespace joshua {

struct LaserTurn {
  std::vector<float> ranges;       // m, index = angle in degrees
  std::vector<float> intensities;
  double rpm;
  double time_increment_s;         // between two readings
  int64_t first_reading_ns;        // wall clock
};

class Lds01 {
 public:
  static constexpr int DEFAULT_BAUD_RATE = 230400;
  static constexpr double RANGE_MIN_M = 0.12;
  static constexpr double RANGE_MAX_M = 3.5;
  static constexpr int READINGS_PER_TURN = 360;

  Lds01(const std::string& port, int baud_rate) : port_(port, baud_rate) {}
  ~Lds01() { close(); }

  // Opens the port, discards stale input and starts the motor.
  void open();
  // Stops the motor and releases the port (never throws).
  void close();
  // Reads what has arrived and returns the next complete turn, if any. DeviceError when no usable
  // turn came for SILENT_DEVICE_TIMEOUT after opening, or for STREAM_SILENCE_TIMEOUT once it streamed.
  std::optional<LaserTurn> poll();

 private:
  std::optional<LaserTurn> assemble(const uint8_t* turn, std::chrono::system_clock::time_point received_at);

  SerialPort port_;
  std::vector<uint8_t> buffer_;
  bool streaming_ = false;
  std::chrono::steady_clock::time_point last_turn_;
};

}  // namespace joshua
