// LDS-01 turn assembly: 60 packets of 42 bytes, 6 readings each (see spec/protocols.md).
#include "drivers/lds01.hpp"

#include <algorithm>
#include <sys/stat.h>

#include "joshua_rcl/errors.hpp"

namespace joshua {
namespace {

constexpr uint8_t START_BYTE = 0xFA;
constexpr uint8_t FIRST_INDEX = 0xA0;
constexpr size_t PACKET_BYTES = 42;
constexpr size_t PACKETS_PER_TURN = 60;
constexpr size_t READINGS_PER_PACKET = 6;
constexpr size_t READING_BYTES = 6;
constexpr size_t READINGS_OFFSET = 4;
constexpr size_t TURN_BYTES = PACKETS_PER_TURN * PACKET_BYTES;
constexpr double SPEED_SCALE = 10;  // speed field = rpm x 10
// No usable turn this long after opening: the device is not streaming (time for the motor to spin up).
constexpr std::chrono::seconds SILENT_DEVICE_TIMEOUT{2};
// No usable turn this long once the device has streamed: it stopped (DEVICE_SILENCE_S of joshua_core.device_link).
constexpr std::chrono::seconds STREAM_SILENCE_TIMEOUT{1};
constexpr size_t READ_CHUNK_BYTES = 4096;
const uint8_t START_COMMAND = 'b';
const uint8_t STOP_COMMAND = 'e';

unsigned little_u16(const uint8_t* data) { return data[0] | (data[1] << 8); }

}  // namespace

void Lds01::open() {
  struct stat info;
  if (::stat(port_.path().c_str(), &info) != 0) {
    throw DeviceError("cannot open LDS-01 lidar at " + port_.path() + ": No such file or directory");
  }
  try {
    port_.open();
    port_.write_all(&START_COMMAND, 1);
  } catch (const DeviceError& error) {
    port_.close();
    throw DeviceError("cannot open LDS-01 lidar at " + port_.path() + ": " + error.what());
  }
  buffer_.clear();
  streaming_ = false;
  last_turn_ = std::chrono::steady_clock::now();
}

void Lds01::close() {
  if (!port_.is_open()) return;
  try {
    port_.write_all(&STOP_COMMAND, 1);
  } catch (const DeviceError&) {
  }
  port_.close();
}

std::optional<LaserTurn> Lds01::poll() {
  uint8_t chunk[READ_CHUNK_BYTES];
  try {
    size_t got;
    while ((got = port_.read_some(chunk, sizeof chunk, 0)) > 0) buffer_.insert(buffer_.end(), chunk, chunk + got);
  } catch (const DeviceError& error) {
    throw DeviceError("LDS-01 lidar at " + port_.path() + " stopped answering: " + error.what());
  }
  while (true) {
    const uint8_t sync[] = {START_BYTE, FIRST_INDEX};
    auto start = std::search(buffer_.begin(), buffer_.end(), sync, sync + 2);
    if (start == buffer_.end()) {
      // Keep a trailing 0xFA: it may be the first half of a sync split across reads.
      const bool keep = !buffer_.empty() && buffer_.back() == START_BYTE;
      buffer_.erase(buffer_.begin(), buffer_.end() - (keep ? 1 : 0));
      break;
    }
    buffer_.erase(buffer_.begin(), start);
    if (buffer_.size() < TURN_BYTES) break;
    std::optional<LaserTurn> turn = assemble(buffer_.data(), std::chrono::system_clock::now());
    buffer_.erase(buffer_.begin(), buffer_.begin() + TURN_BYTES);
    if (turn) {
      streaming_ = true;
      last_turn_ = std::chrono::steady_clock::now();
      return turn;
    }
  }
  const auto silent = std::chrono::steady_clock::now() - last_turn_;
  if (streaming_ && silent > STREAM_SILENCE_TIMEOUT) {
    throw DeviceError("LDS-01 lidar at " + port_.path() + " stopped streaming: no usable scan for " +
                      std::to_string(STREAM_SILENCE_TIMEOUT.count()) + " s");
  }
  if (!streaming_ && silent > SILENT_DEVICE_TIMEOUT) {
    throw DeviceError("LDS-01 lidar at " + port_.path() + " sent no usable scan within " +
                      std::to_string(SILENT_DEVICE_TIMEOUT.count()) +
                      " s (silent device, wrong baud rate or not an LDS-01)");
  }
  return std::nullopt;
}

std::optional<LaserTurn> Lds01::assemble(const uint8_t* turn, std::chrono::system_clock::time_point received_at) {
  LaserTurn scan;
  scan.ranges.assign(READINGS_PER_TURN, 0.0f);
  scan.intensities.assign(READINGS_PER_TURN, 0.0f);
  double speed_sum = 0;
  int good = 0;
  for (size_t k = 0; k < PACKETS_PER_TURN; ++k) {
    const uint8_t* packet = turn + k * PACKET_BYTES;
    const unsigned speed = little_u16(packet + 2);
    if (packet[0] != START_BYTE || packet[1] != FIRST_INDEX + k || speed == 0) continue;
    ++good;
    speed_sum += speed;
    for (size_t j = 0; j < READINGS_PER_PACKET; ++j) {
      const uint8_t* reading = packet + READINGS_OFFSET + j * READING_BYTES;
      const size_t index = READINGS_PER_TURN - 1 - (k * READINGS_PER_PACKET + j);
      scan.intensities[index] = static_cast<float>(little_u16(reading));
      scan.ranges[index] = static_cast<float>(little_u16(reading + 2) / 1000.0);
    }
  }
  if (good == 0) return std::nullopt;
  scan.rpm = speed_sum / good / SPEED_SCALE;
  scan.time_increment_s = 1.0 / (scan.rpm * 6.0);
  // Stamp of the first reading: the turn ended when its last byte arrived.
  const int64_t received_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(received_at.time_since_epoch()).count();
  scan.first_reading_ns = received_ns - static_cast<int64_t>(scan.time_increment_s * READINGS_PER_TURN * 1e9);
  return scan;
}

}  // namespace joshua
