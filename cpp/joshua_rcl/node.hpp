// One ROS 2 node on rcl: context and name from argv, parameters, endpoints, timers and the wait loop.
//
//     int main(int argc, char** argv) {
//       MyNode app;                                  // an Application: start() and close()
//       joshua::run(argc, argv, "my_node", app);
//     }
//
// run() installs the SIGINT/SIGTERM handlers, starts the node, announces it ready (one "ready: ..." line
// and READY=1 to the process manager, see notify.hpp; an Application with ready_later() announces itself),
// spins until a signal arrives (pinging the manager's watchdog), calls close(), destroys the node and ends
// the process with the exit code of the Python runtime: 0 after a signal (also during start-up), else the JoshuaError's code with one
// line `NAME: error: ...` on stderr. It does not return.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "joshua_rcl/endpoints.hpp"
#include "joshua_rcl/parameters.hpp"
#include "rcl/context.h"
#include "rcl/guard_condition.h"
#include "rcl/node.h"
#include "rcl/wait.h"

namespace joshua {

class Notifier;
class StopListener;
using Clock = std::chrono::steady_clock;

class Node {
 public:
  // Parses `--ros-args` (remapping `__node:=NAME`, `-p k:=v`) with rcl; `default_name` without `__node`.
  Node(int argc, char** argv, const std::string& default_name);
  ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  const std::string& name() const { return name_; }
  const Parameters& parameters() const { return *parameters_; }

  template <class Message>
  Publisher<Message>& publisher(const std::string& topic, const rmw_qos_profile_t& qos) {
    auto owned = std::make_unique<Publisher<Message>>(&node_, topic, qos);
    Publisher<Message>& publisher = *owned;
    published_.push_back(topic);
    entities_.push_back(std::move(owned));
    return publisher;
  }

  template <class Message>
  void subscribe(const std::string& topic, const rmw_qos_profile_t& qos,
                 typename Subscription<Message>::Callback callback) {
    auto owned = std::make_unique<Subscription<Message>>(&node_, topic, qos, std::move(callback));
    subscribed_.push_back(topic);
    subscriptions_.push_back(owned.get());
    entities_.push_back(std::move(owned));
  }

  // Calls `callback` every `period_s` seconds from the wait loop (missed ticks are skipped).
  void every(double period_s, std::function<void()> callback);

  // Runs timers and subscription callbacks until SIGINT or SIGTERM. Between them it sleeps in rcl_wait
  // until a message, the next timer or watchdog ping, or a stop signal (which triggers stop_guard_).
  void spin();

  // Logs "ready: [detail; ]<what it serves>" and sends READY=1; later calls do nothing.
  void announce_ready(const std::string& detail = "");
  // "publishing /a, /b subscribing /c at 100 Hz on /dev/ttyUSB0", as the Python runtime says it.
  std::string serving() const;

  void info(const std::string& message) const;
  void warn(const std::string& message) const;

 private:
  struct Timer {
    Clock::duration period;
    Clock::time_point next;
    std::function<void()> callback;
  };

  void wait_for_work(std::optional<Clock::time_point> until);
  void run_due_timers();

  rcl_context_t context_ = rcl_get_zero_initialized_context();
  rcl_node_t node_ = rcl_get_zero_initialized_node();
  rcl_wait_set_t wait_set_ = rcl_get_zero_initialized_wait_set();
  rcl_guard_condition_t stop_guard_ = rcl_get_zero_initialized_guard_condition();
  std::unique_ptr<StopListener> stop_listener_;  // triggers stop_guard_; ends before the guard condition
  std::string name_;
  std::unique_ptr<Parameters> parameters_;
  std::vector<std::unique_ptr<Entity>> entities_;
  std::vector<SubscriptionBase*> subscriptions_;
  std::vector<Timer> timers_;
  std::vector<std::string> published_, subscribed_;
  std::unique_ptr<Notifier> notifier_;
  bool ready_ = false;
};

// What a node binary does on top of a Node: open devices and create endpoints, then release them.
class Application {
 public:
  virtual ~Application() = default;
  virtual void start(Node& node) = 0;
  // True when the node announces itself ready later (Node::announce_ready), e.g. on its first message.
  virtual bool ready_later() const { return false; }
  // Called once after spinning stops, also after a failed start.
  virtual void close() {}
};

[[noreturn]] void run(int argc, char** argv, const std::string& default_name, Application& application);

}  // namespace joshua
