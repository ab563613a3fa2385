// SIGINT/SIGTERM handling: the handler records the request and wakes whoever waits for it.
//
// The handler only sets a flag and writes one byte to a pipe (both async-signal-safe). A watcher
// thread blocked on that pipe calls the registered wake function (a StopListener), which may do what
// a handler must not, such as triggering an rcl guard condition so that rcl_wait returns at once.
#pragma once

#include <functional>

namespace joshua {

// Install the SIGINT and SIGTERM handlers and start the watcher thread (once, before rcl starts).
void install_stop_handlers();

// True once SIGINT or SIGTERM has arrived.
bool stop_requested();

// Throws StopRequested when a stop has been requested (for long start-up steps).
void throw_if_stopping();

// While it lives, `wake` is called on the watcher thread for every SIGINT or SIGTERM (and at once when
// one has already arrived). One listener at a time.
class StopListener {
 public:
  explicit StopListener(std::function<void()> wake);
  ~StopListener();
  StopListener(const StopListener&) = delete;
  StopListener& operator=(const StopListener&) = delete;
};

}  // namespace joshua
