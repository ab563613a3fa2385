// SIGINT/SIGTERM handling through an async-signal-safe flag.
#include "joshua_rcl/signals.hpp"

#include <csignal>

#include "joshua_rcl/errors.hpp"

namespace joshua {
namespace {

volatile std::sig_atomic_t stop_flag = 0;

void on_stop_signal(int) { stop_flag = 1; }

}  // namespace

void install_stop_handlers() {
  struct sigaction action = {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool stop_requested() { return stop_flag != 0; }

void throw_if_stopping() {
  if (stop_requested()) throw StopRequested();
}

}  // namespace joshua
