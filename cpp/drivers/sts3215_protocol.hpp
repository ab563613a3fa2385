// Feetech SCS/STS packets (`FF FF ID LEN INST|ERR P1..Pn CHK`) and the STS3215 registers the nodes use.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace joshua::sts3215 {

using Bytes = std::vector<uint8_t>;

constexpr uint8_t BROADCAST_ID = 0xFE;
constexpr uint8_t INST_PING = 0x01;
constexpr uint8_t INST_READ = 0x02;
constexpr uint8_t INST_WRITE = 0x03;
constexpr uint8_t INST_SYNC_READ = 0x82;
constexpr uint8_t INST_SYNC_WRITE = 0x83;
constexpr int MODEL_NUMBER_STS3215 = 777;
constexpr int MAX_TICK = 4095;

struct Register {
  uint8_t address;
  uint8_t size;
  int sign_bit;  // sign-magnitude encoding with this sign bit; -1 for plain unsigned
};

constexpr Register MODEL_NUMBER{3, 2, -1};
constexpr Register MIN_POSITION_LIMIT{9, 2, -1};
constexpr Register MAX_POSITION_LIMIT{11, 2, -1};
constexpr Register HOMING_OFFSET{31, 2, 11};
constexpr Register TORQUE_ENABLE{40, 1, -1};
constexpr Register GOAL_POSITION{42, 2, 15};
constexpr Register LOCK{55, 1, -1};
constexpr Register PRESENT_POSITION{56, 2, 15};
constexpr Register PRESENT_VELOCITY{58, 2, 15};
constexpr Register PRESENT_LOAD{60, 2, 10};
constexpr Register PRESENT_VOLTAGE{62, 1, -1};
constexpr Register PRESENT_TEMPERATURE{63, 1, -1};
constexpr Register STATUS{65, 1, -1};
constexpr Register MOVING{66, 1, -1};
constexpr Register PRESENT_CURRENT{69, 2, -1};
// Factory protection settings (control table defaults) the health of a servo is judged against.
constexpr int DEFAULT_MAX_TEMPERATURE_C = 70;
constexpr int DEFAULT_MAX_VOLTAGE = 140;  // 0.1 V
constexpr int DEFAULT_MIN_VOLTAGE = 40;   // 0.1 V
constexpr int DEFAULT_MAX_TORQUE = 1000;  // 0.1 %
constexpr int DEFAULT_OVERLOAD_TORQUE = 80;  // %
// Bits of the status ERR byte and of the Status register, with their names, in bit order.
constexpr std::pair<uint8_t, const char*> ERROR_NAMES[] = {
    {0x01, "input voltage"}, {0x02, "angle sensor"}, {0x04, "overheat"}, {0x08, "over-current"}, {0x20, "overload"}};
// Model_Number .. Response_Status_Level in one READ.
constexpr uint8_t IDENTITY_ADDRESS = 3;
constexpr uint8_t IDENTITY_SIZE = 6;
// Present_Position, Present_Velocity, Present_Load in one SYNC_READ.
constexpr uint8_t STATE_ADDRESS = 56;
constexpr uint8_t STATE_SIZE = 6;
// Present_Position .. Present_Current (the telemetry a servo's health is judged by) in one SYNC_READ.
constexpr uint8_t TELEMETRY_ADDRESS = 56;
constexpr uint8_t TELEMETRY_SIZE = 15;

struct Packet {
  uint8_t servo_id;
  uint8_t code;  // INST for instructions, ERR for status packets
  Bytes params;
  bool checksum_ok;
};

Bytes encode(uint8_t servo_id, uint8_t code, const Bytes& params = {});
Bytes encode_sync_read(uint8_t address, uint8_t size, const std::vector<uint8_t>& ids);
Bytes encode_sync_write(const Register& reg, const std::vector<std::pair<uint8_t, int>>& values);

// Little-endian register bytes of a value, sign-magnitude where the register uses it.
Bytes encode_value(const Register& reg, int value);
int decode_value(const Register& reg, const uint8_t* data);

// Incremental decoder: feed() bytes, then pop() packets. A frame with a bad checksum is returned once
// with checksum_ok false and only its first byte consumed, so a packet hidden inside it is still found.
// `discarded()` counts bytes that framed no valid packet (noise, two servos answering at once).
class PacketParser {
 public:
  void feed(const uint8_t* data, size_t size) { buffer_.insert(buffer_.end(), data, data + size); }
  void clear() { buffer_.clear(); }
  std::optional<Packet> pop();
  size_t pending() const { return buffer_.size(); }
  size_t discarded() const { return discarded_; }

 private:
  void drop(size_t count);

  Bytes buffer_;
  size_t discarded_ = 0;
};

}  // namespace joshua::sts3215
