// STS3215 transactions over a SerialPort, with the Python driver's timeouts, retries and messages.
#include "drivers/sts3215_bus.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "joshua_rcl/errors.hpp"
#include "joshua_rcl/signals.hpp"

namespace joshua {
namespace {

using namespace sts3215;
using SteadyClock = std::chrono::steady_clock;

constexpr double REPLY_TIMEOUT_S = 0.02;  // wait for a status packet beyond its own transmission time
constexpr int MAX_RETRIES = 3;            // extra attempts after a timeout or a corrupt reply
constexpr size_t READ_CHUNK_BYTES = 512;
constexpr double BITS_PER_BYTE = 10;  // 8N1
constexpr size_t STATUS_OVERHEAD_BYTES = 6;
constexpr double LOAD_FULL_SCALE = 1000.0;
enum Reply { REPLY_OK, REPLY_TIMEOUT, REPLY_CORRUPT, REPLY_GARBLED };

double seconds_since(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

}  // namespace

Sts3215Bus::Sts3215Bus(const std::string& port, int baud_rate, std::vector<int> ids,
                       std::vector<MotorCalibration> calibration, bool calibrated)
    : port_(port, baud_rate), ids_(ids.begin(), ids.end()), calibration_(std::move(calibration)),
      calibrated_(calibrated), acknowledges_(ids_.size(), true) {}

void Sts3215Bus::open(bool list_every_missing) {
  port_.open();
  parser_.clear();
  try {
    check_servos(list_every_missing);
    if (calibrated_) store_calibration();
  } catch (...) {
    port_.close();
    throw;
  }
  ++connections_;
}

void Sts3215Bus::ensure_open() {
  if (!port_.is_open()) open(false);
}

void Sts3215Bus::check_servos(bool list_every_missing) {
  std::string missing, wrong;
  for (size_t i = 0; i < ids_.size(); ++i) {
    throw_if_stopping();
    const uint8_t servo_id = ids_[i];
    Bytes identity;
    try {
      transact(encode(servo_id, INST_PING), {{servo_id, 0}});
      identity = read_block(servo_id, IDENTITY_ADDRESS, IDENTITY_SIZE);
    } catch (const DeviceError&) {
      if (!port_.is_open()) throw;
      missing += (missing.empty() ? "" : ", ") + std::to_string(servo_id);
      if (!list_every_missing) break;
      continue;
    }
    const int model = decode_value(MODEL_NUMBER, identity.data());
    if (model != MODEL_NUMBER_STS3215) {
      wrong += (wrong.empty() ? "" : "; ") + std::string("servo id ") + std::to_string(servo_id) + " is model " +
               std::to_string(model) + ", expected STS3215 (" + std::to_string(MODEL_NUMBER_STS3215) + ")";
    }
    acknowledges_[i] = identity[5] >= 1;
  }
  if (!missing.empty()) throw DeviceError(port() + ": no answer from servo id " + missing);
  if (!wrong.empty()) throw DeviceError(port() + ": " + wrong);
}

void Sts3215Bus::store_calibration() {
  for (size_t i = 0; i < ids_.size(); ++i) {
    const MotorCalibration& motor = calibration_[i];
    const uint8_t servo_id = ids_[i];
    if (read_register(servo_id, HOMING_OFFSET) == motor.homing_offset &&
        read_register(servo_id, MIN_POSITION_LIMIT) == motor.range_min &&
        read_register(servo_id, MAX_POSITION_LIMIT) == motor.range_max) {
      continue;
    }
    write_register(servo_id, TORQUE_ENABLE, 0);
    write_register(servo_id, LOCK, 0);
    write_register(servo_id, HOMING_OFFSET, motor.homing_offset);
    write_register(servo_id, MIN_POSITION_LIMIT, motor.range_min);
    write_register(servo_id, MAX_POSITION_LIMIT, motor.range_max);
    write_register(servo_id, LOCK, 1);
  }
}

Bytes Sts3215Bus::read_block(uint8_t servo_id, uint8_t address, uint8_t size) {
  return transact(encode(servo_id, INST_READ, {address, size}), {{servo_id, size}})[0].params;
}

int Sts3215Bus::read_register(uint8_t servo_id, const Register& reg) {
  return decode_value(reg, read_block(servo_id, reg.address, reg.size).data());
}

void Sts3215Bus::write_register(uint8_t servo_id, const Register& reg, int value) {
  Bytes params = {reg.address};
  const Bytes data = encode_value(reg, value);
  params.insert(params.end(), data.begin(), data.end());
  const Bytes packet = encode(servo_id, INST_WRITE, params);
  size_t index = 0;
  while (index < ids_.size() && ids_[index] != servo_id) ++index;
  if (index == ids_.size() || acknowledges_[index]) {
    transact(packet, {{servo_id, 0}});
  } else {
    send(packet);
  }
}

std::vector<Packet> Sts3215Bus::transact(const Bytes& packet, const std::vector<Expected>& expected) {
  const int attempts = 1 + MAX_RETRIES;
  int failure = REPLY_TIMEOUT;
  uint8_t failed_id = 0;
  for (int attempt = 0; attempt < attempts; ++attempt) {
    port_.discard_input();  // late replies to earlier requests
    parser_.clear();
    send(packet);
    std::vector<Packet> replies;
    for (const Expected& item : expected) {
      Packet reply;
      failure = receive(item, reply);
      if (failure != REPLY_OK) {
        failed_id = item.servo_id;
        break;
      }
      replies.push_back(std::move(reply));
    }
    if (failure == REPLY_OK) return replies;
  }
  const char* what = failure == REPLY_CORRUPT   ? "corrupt replies from"
                     : failure == REPLY_GARBLED ? "garbled replies from"
                                                : "no answer from";
  throw DeviceError(port() + ": " + what + " servo id " + std::to_string(failed_id) + " after " +
                    std::to_string(attempts) + " attempts");
}

int Sts3215Bus::receive(const Expected& item, Packet& packet) {
  const size_t reply_bytes = STATUS_OVERHEAD_BYTES + item.param_bytes;
  const double timeout = REPLY_TIMEOUT_S + reply_bytes * BITS_PER_BYTE / port_.baud_rate();
  const SteadyClock::time_point start = SteadyClock::now();
  const size_t discarded_before = parser_.discarded();
  uint8_t chunk[READ_CHUNK_BYTES];
  bool looked_after_deadline = false;
  while (true) {
    if (auto popped = parser_.pop()) {
      if (!popped->checksum_ok) return REPLY_CORRUPT;
      if (popped->servo_id != item.servo_id) continue;  // a late answer to an earlier request
      if (popped->params.size() != item.param_bytes) return REPLY_CORRUPT;
      packet = std::move(*popped);
      return REPLY_OK;
    }
    if (looked_after_deadline) {
      // Bytes that framed no packet: usually two servos answering to one id.
      const bool garbled = parser_.pending() > 0 || parser_.discarded() > discarded_before;
      return garbled ? REPLY_GARBLED : REPLY_TIMEOUT;
    }
    // Past the deadline, one last look: a reply that came in time is in the buffer even when this
    // thread was kept off the CPU until after the deadline.
    const double remaining = timeout - seconds_since(start);
    looked_after_deadline = remaining <= 0;
    const size_t got = port_.read_some(chunk, sizeof chunk, std::max(remaining, 0.0));
    parser_.feed(chunk, got);
  }
}

std::vector<Packet> Sts3215Bus::sync_read_block(uint8_t address, uint8_t size) {
  std::vector<Expected> expected;
  for (uint8_t servo_id : ids_) expected.push_back({servo_id, size});
  return transact(encode_sync_read(address, size, ids_), expected);
}

void Sts3215Bus::sync_write(const Register& reg, const std::vector<std::pair<uint8_t, int>>& values) {
  if (values.empty()) return;
  ensure_open();
  send(encode_sync_write(reg, values));
}

std::vector<JointReading> Sts3215Bus::read_state() {
  ensure_open();
  const std::vector<Packet> packets = sync_read_block(STATE_ADDRESS, STATE_SIZE);
  std::vector<JointReading> readings;
  for (size_t i = 0; i < packets.size(); ++i) {
    const uint8_t* data = packets[i].params.data();
    const MotorCalibration& motor = calibration_[i];
    readings.push_back({motor.to_radians(decode_value(PRESENT_POSITION, data)),
                        motor.speed_to_radians(decode_value(PRESENT_VELOCITY, data + 2)),
                        motor.sign() * decode_value(PRESENT_LOAD, data + 4) / LOAD_FULL_SCALE});
  }
  return readings;
}

void Sts3215Bus::write_goals(const std::vector<double>& radians) {
  std::vector<std::pair<uint8_t, int>> goals;
  for (size_t i = 0; i < ids_.size() && i < radians.size(); ++i) {
    if (!std::isnan(radians[i])) goals.emplace_back(ids_[i], calibration_[i].to_ticks(radians[i]));
  }
  sync_write(GOAL_POSITION, goals);
}

void Sts3215Bus::hold_present_pose() {
  ensure_open();
  const std::vector<Packet> packets = sync_read_block(PRESENT_POSITION.address, PRESENT_POSITION.size);
  std::vector<std::pair<uint8_t, int>> present;
  for (const Packet& packet : packets) {
    present.emplace_back(packet.servo_id, decode_value(PRESENT_POSITION, packet.params.data()));
  }
  sync_write(GOAL_POSITION, present);
}

void Sts3215Bus::enable_torque() {
  hold_present_pose();
  std::vector<std::pair<uint8_t, int>> on;
  for (uint8_t servo_id : ids_) on.emplace_back(servo_id, 1);
  sync_write(TORQUE_ENABLE, on);
}

std::vector<Bytes> Sts3215Bus::read_blocks(uint8_t address, uint8_t size) {
  ensure_open();
  std::vector<Bytes> blocks;
  for (Packet& packet : sync_read_block(address, size)) blocks.push_back(std::move(packet.params));
  return blocks;
}

void Sts3215Bus::disable_torque() {
  std::vector<std::pair<uint8_t, int>> off;
  for (uint8_t servo_id : ids_) off.emplace_back(servo_id, 0);
  sync_write(TORQUE_ENABLE, off);
}

}  // namespace joshua
