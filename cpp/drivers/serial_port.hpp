// A raw 8N1 serial port over termios (any baud rate), opened exclusively and read without blocking.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

namespace joshua {

class SerialPort {
 public:
  SerialPort(std::string path, int baud_rate) : path_(std::move(path)), baud_rate_(baud_rate) {}
  ~SerialPort() { close(); }
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  const std::string& path() const { return path_; }
  int baud_rate() const { return baud_rate_; }
  bool is_open() const { return fd_ >= 0; }

  // DeviceError "serial port P not found" / "cannot open serial port P: reason".
  void open();
  void close();
  // Writes every byte (waiting at most WRITE_TIMEOUT for room); DeviceError and closed when the port is gone.
  void write_all(const uint8_t* data, size_t size);
  // Waits up to `wait_s` for input and returns what is there (0 bytes after the wait).
  size_t read_some(uint8_t* buffer, size_t capacity, double wait_s);
  // Drops unread input.
  void discard_input();

 private:
  [[noreturn]] void lost(int error);

  std::string path_;
  int baud_rate_;
  int fd_ = -1;
};

}  // namespace joshua
