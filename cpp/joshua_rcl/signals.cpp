// SIGINT/SIGTERM handling through an async-signal-safe flag and a self-pipe read by a watcher thread.
#include "joshua_rcl/signals.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <mutex>
#include <system_error>
#include <thread>

#include "joshua_rcl/errors.hpp"

namespace joshua {
namespace {

volatile std::sig_atomic_t stop_flag = 0;
int wake_pipe[2] = {-1, -1};  // [0] read by the watcher thread, [1] written by the handler

std::mutex listener_mutex;
std::function<void()> listener;  // guarded by listener_mutex

void on_stop_signal(int) {
  stop_flag = 1;
  const int saved_errno = errno;
  const char byte = 1;
  [[maybe_unused]] const ssize_t written = ::write(wake_pipe[1], &byte, 1);  // a full pipe already wakes
  errno = saved_errno;
}

void call_listener() {
  std::lock_guard<std::mutex> lock(listener_mutex);
  if (listener) listener();
}

// Runs for the life of the process; signals are blocked here, so the handler runs on other threads.
void watch_stop_pipe() {
  sigset_t stops;
  sigemptyset(&stops);
  sigaddset(&stops, SIGINT);
  sigaddset(&stops, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stops, nullptr);
  char bytes[64];
  while (true) {
    const ssize_t count = ::read(wake_pipe[0], bytes, sizeof bytes);
    if (count > 0) call_listener();
    if (count == 0 || (count < 0 && errno != EINTR)) return;
  }
}

}  // namespace

void install_stop_handlers() {
  if (wake_pipe[0] >= 0) return;
  if (::pipe2(wake_pipe, O_CLOEXEC) != 0) throw std::system_error(errno, std::generic_category(), "stop pipe");
  ::fcntl(wake_pipe[1], F_SETFL, O_NONBLOCK);  // the handler must never block
  std::thread(watch_stop_pipe).detach();
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

StopListener::StopListener(std::function<void()> wake) {
  std::lock_guard<std::mutex> lock(listener_mutex);
  listener = std::move(wake);
  if (stop_requested()) listener();
}

StopListener::~StopListener() {
  std::lock_guard<std::mutex> lock(listener_mutex);
  listener = nullptr;
}

}  // namespace joshua
