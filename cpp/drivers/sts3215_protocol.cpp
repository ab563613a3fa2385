// Packet encoding, checksum, sign-magnitude values and the resynchronising packet parser.
#include "drivers/sts3215_protocol.hpp"

#include <algorithm>
#include <cstdlib>

namespace joshua::sts3215 {
namespace {

constexpr uint8_t HEADER_BYTE = 0xFF;
constexpr uint8_t MAX_LENGTH = 250;

uint8_t checksum(const uint8_t* body, size_t size) {
  unsigned sum = 0;
  for (size_t i = 0; i < size; ++i) sum += body[i];
  return static_cast<uint8_t>(~sum & 0xFF);
}

}  // namespace

Bytes encode(uint8_t servo_id, uint8_t code, const Bytes& params) {
  Bytes packet = {HEADER_BYTE, HEADER_BYTE, servo_id, static_cast<uint8_t>(params.size() + 2), code};
  packet.insert(packet.end(), params.begin(), params.end());
  packet.push_back(checksum(packet.data() + 2, packet.size() - 2));
  return packet;
}

Bytes encode_sync_read(uint8_t address, uint8_t size, const std::vector<uint8_t>& ids) {
  Bytes params = {address, size};
  params.insert(params.end(), ids.begin(), ids.end());
  return encode(BROADCAST_ID, INST_SYNC_READ, params);
}

Bytes encode_sync_write(const Register& reg, const std::vector<std::pair<uint8_t, int>>& values) {
  Bytes params = {reg.address, reg.size};
  for (const auto& [servo_id, value] : values) {
    params.push_back(servo_id);
    const Bytes data = encode_value(reg, value);
    params.insert(params.end(), data.begin(), data.end());
  }
  return encode(BROADCAST_ID, INST_SYNC_WRITE, params);
}

Bytes encode_value(const Register& reg, int value) {
  unsigned raw = static_cast<unsigned>(value);
  if (reg.sign_bit >= 0) {
    const unsigned limit = (1u << reg.sign_bit) - 1;
    const unsigned magnitude = std::min(static_cast<unsigned>(std::abs(value)), limit);
    raw = value < 0 ? magnitude | (1u << reg.sign_bit) : magnitude;
  }
  Bytes data(reg.size);
  for (size_t i = 0; i < reg.size; ++i) data[i] = static_cast<uint8_t>(raw >> (8 * i));
  return data;
}

int decode_value(const Register& reg, const uint8_t* data) {
  unsigned raw = 0;
  for (size_t i = 0; i < reg.size; ++i) raw |= static_cast<unsigned>(data[i]) << (8 * i);
  if (reg.sign_bit < 0) return static_cast<int>(raw);
  const int magnitude = static_cast<int>(raw & ((1u << reg.sign_bit) - 1));
  return raw & (1u << reg.sign_bit) ? -magnitude : magnitude;
}

void PacketParser::drop(size_t count) {
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<long>(count));
  discarded_ += count;
}

std::optional<Packet> PacketParser::pop() {
  while (true) {
    size_t start = 0;
    while (start + 1 < buffer_.size() && !(buffer_[start] == HEADER_BYTE && buffer_[start + 1] == HEADER_BYTE)) {
      ++start;
    }
    if (start + 1 >= buffer_.size()) {
      // Keep a trailing FF: it may be the first half of the next header.
      const bool keep = !buffer_.empty() && buffer_.back() == HEADER_BYTE;
      drop(buffer_.size() - (keep ? 1 : 0));
      return std::nullopt;
    }
    drop(start);
    if (buffer_.size() < 4) return std::nullopt;
    if (buffer_[2] == HEADER_BYTE) {  // FF FF FF: the header starts one byte later
      drop(1);
      continue;
    }
    const uint8_t length = buffer_[3];
    if (length < 2 || length > MAX_LENGTH) {
      drop(1);
      continue;
    }
    const size_t total = length + 4u;
    if (buffer_.size() < total) return std::nullopt;
    const bool ok = checksum(buffer_.data() + 2, total - 3) == buffer_[total - 1];
    Packet packet{buffer_[2], buffer_[4], Bytes(buffer_.begin() + 5, buffer_.begin() + static_cast<long>(total) - 1),
                  ok};
    if (ok) {
      buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<long>(total));
    } else {
      drop(1);
    }
    return packet;
  }
}

}  // namespace joshua::sts3215
