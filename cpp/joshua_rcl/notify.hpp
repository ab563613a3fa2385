// The sd_notify protocol, sending side (as joshua_runtime.notify): READY=1, STATUS=, WATCHDOG=1, STOPPING=1.
//
// systemd (Type=notify) and supervisor.py hand a node NOTIFY_SOCKET, a Unix datagram socket (a path, or
// `@name` in the abstract namespace). Without it every call does nothing; sending never fails the node.
#pragma once

#include <optional>
#include <string>

#include "joshua_rcl/node.hpp"

namespace joshua {

class Notifier {
 public:
  // The manager's notifier; NOTIFY_SOCKET, WATCHDOG_USEC and WATCHDOG_PID are taken out of the
  // environment, so no child process speaks for the node.
  static Notifier from_environment();
  ~Notifier();
  Notifier(Notifier&& other) noexcept;
  Notifier(const Notifier&) = delete;
  Notifier& operator=(const Notifier&) = delete;

  void ready(const std::string& status) { send("READY=1\nSTATUS=" + status); }
  void stopping() { send("STOPPING=1"); }
  // Pings the watchdog when half its interval has passed since the last ping.
  void watchdog(Clock::time_point now);
  // When the next watchdog ping is due; none without a watchdog.
  std::optional<Clock::time_point> watchdog_due() const;

 private:
  Notifier() = default;
  void send(const std::string& datagram);

  std::string address_;  // sockaddr_un path bytes ("\0name" for the abstract namespace); empty: none
  std::optional<Clock::duration> watchdog_interval_;
  std::optional<Clock::time_point> last_watchdog_;
  int socket_ = -1;
};

}  // namespace joshua
