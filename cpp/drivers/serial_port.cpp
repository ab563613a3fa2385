// termios2 (BOTHER) configuration, so that any baud rate works, not only the Bxxx constants.
#include "drivers/serial_port.hpp"

#include <asm/termbits.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "joshua_rcl/errors.hpp"

namespace joshua {
namespace {

const int WRITE_TIMEOUT_MS = 100;  // a write that cannot be queued in this time means a dead port

std::string reason(int error) { return std::strerror(error); }

int milliseconds(double seconds) { return seconds <= 0 ? 0 : static_cast<int>(seconds * 1000.0 + 0.999); }

}  // namespace

void SerialPort::open() {
  if (fd_ >= 0) return;
  struct stat info;
  if (::stat(path_.c_str(), &info) != 0) throw DeviceError("serial port " + path_ + " not found");
  const int fd = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw DeviceError("cannot open serial port " + path_ + ": " + reason(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EWOULDBLOCK) throw DeviceError("serial port " + path_ + " is busy: another program has it open");
    throw DeviceError("cannot open serial port " + path_ + ": " + reason(error));
  }
  struct termios2 tty = {};
  tty.c_cflag = CS8 | CREAD | CLOCAL | BOTHER | (BOTHER << IBSHIFT);
  tty.c_ispeed = tty.c_ospeed = static_cast<speed_t>(baud_rate_);
  if (::ioctl(fd, TCSETS2, &tty) != 0) {
    const int error = errno;
    ::close(fd);
    throw DeviceError("cannot configure serial port " + path_ + ": " + reason(error));
  }
  ::ioctl(fd, TCFLSH, TCIFLUSH);
  fd_ = fd;
}

void SerialPort::close() {
  if (fd_ < 0) return;
  ::close(fd_);
  fd_ = -1;
}

void SerialPort::lost(int error) {
  close();
  throw DeviceError("serial port " + path_ + " disconnected: " + reason(error));
}

void SerialPort::write_all(const uint8_t* data, size_t size) {
  if (fd_ < 0) throw DeviceError("serial port " + path_ + " is not open");
  while (size > 0) {
    const ssize_t written = ::write(fd_, data, size);
    if (written > 0) {
      data += written;
      size -= static_cast<size_t>(written);
      continue;
    }
    if (written < 0 && errno == EINTR) continue;
    if (written < 0 && errno != EAGAIN) lost(errno);
    struct pollfd room = {fd_, POLLOUT, 0};
    const int ready = ::poll(&room, 1, WRITE_TIMEOUT_MS);
    if (ready == 0) lost(ETIMEDOUT);
    if (ready < 0 && errno != EINTR) lost(errno);
    if (ready > 0 && (room.revents & (POLLERR | POLLHUP | POLLNVAL))) lost(EIO);
  }
}

size_t SerialPort::read_some(uint8_t* buffer, size_t capacity, double wait_s) {
  if (fd_ < 0) throw DeviceError("serial port " + path_ + " is not open");
  struct pollfd input = {fd_, POLLIN, 0};
  const int ready = ::poll(&input, 1, milliseconds(wait_s));
  if (ready < 0) {
    if (errno == EINTR) return 0;
    lost(errno);
  }
  if (ready == 0) return 0;
  if (input.revents & (POLLERR | POLLNVAL)) lost(EIO);
  const ssize_t got = ::read(fd_, buffer, capacity);
  if (got > 0) return static_cast<size_t>(got);
  if (got < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  lost(got == 0 || (input.revents & POLLHUP) ? EIO : errno);
}

void SerialPort::discard_input() {
  if (fd_ >= 0) ::ioctl(fd_, TCFLSH, TCIFLUSH);
}

}  // namespace joshua
