// One AF_UNIX datagram per notification, as systemd's sd_notify sends them.
#include "joshua_rcl/notify.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace joshua {
namespace {

std::string take_variable(const char* name) {
  const char* value = std::getenv(name);
  std::string text = value ? value : "";
  unsetenv(name);
  return text;
}

bool all_digits(const std::string& text) {
  return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
}

}  // namespace

Notifier Notifier::from_environment() {
  Notifier notifier;
  const std::string value = take_variable("NOTIFY_SOCKET");
  const std::string usec = take_variable("WATCHDOG_USEC");
  const std::string watchdog_pid = take_variable("WATCHDOG_PID");
  if (value.size() > 1 && value[0] == '@') notifier.address_ = std::string(1, '\0') + value.substr(1);
  if (!value.empty() && value[0] == '/') notifier.address_ = value;
  const bool ours = watchdog_pid.empty() || watchdog_pid == std::to_string(getpid());
  if (all_digits(usec) && std::stoll(usec) > 0 && ours) {
    notifier.watchdog_interval_ = std::chrono::microseconds(std::stoll(usec));
  }
  return notifier;
}

Notifier::Notifier(Notifier&& other) noexcept
    : address_(std::move(other.address_)), watchdog_interval_(other.watchdog_interval_),
      last_watchdog_(other.last_watchdog_), socket_(other.socket_) {
  other.socket_ = -1;
}

Notifier::~Notifier() {
  if (socket_ >= 0) ::close(socket_);
}

void Notifier::watchdog(Clock::time_point now) {
  if (!watchdog_interval_) return;
  if (last_watchdog_ && now - *last_watchdog_ < *watchdog_interval_ / 2) return;
  last_watchdog_ = now;
  send("WATCHDOG=1");
}

std::optional<Clock::time_point> Notifier::watchdog_due() const {
  if (!watchdog_interval_) return std::nullopt;
  return last_watchdog_ ? *last_watchdog_ + *watchdog_interval_ / 2 : Clock::now();
}

void Notifier::send(const std::string& datagram) {
  sockaddr_un target{};
  if (address_.empty() || address_.size() >= sizeof target.sun_path) return;
  if (socket_ < 0) socket_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (socket_ < 0) return;
  target.sun_family = AF_UNIX;
  std::memcpy(target.sun_path, address_.data(), address_.size());
  const socklen_t length = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + address_.size());
  ::sendto(socket_, datagram.data(), datagram.size(), MSG_NOSIGNAL, reinterpret_cast<const sockaddr*>(&target), length);
}

}  // namespace joshua
