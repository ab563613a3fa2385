// rcl context, node and wait loop behind joshua::Node, and the run() wrapper giving exit codes.
#include "joshua_rcl/node.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <set>
#include <sstream>

#include "joshua_rcl/notify.hpp"
#include "joshua_rcl/signals.hpp"
#include "rcl/arguments.h"
#include "rcl/init.h"
#include "rcl/init_options.h"

namespace joshua {
namespace {

void log_line(const char* level, const std::string& node, const std::string& message) {
  const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  std::fprintf(stderr, "[%s] [%.9f] [%s]: %s\n", level, now, node.c_str(), message.c_str());
  std::fflush(stderr);
}

// Parses the arguments once before rcl_init, which only logs "Failed to parse global arguments".
void check_arguments(int argc, char** argv, rcl_allocator_t allocator) {
  rcl_arguments_t arguments = rcl_get_zero_initialized_arguments();
  const rcl_ret_t parsed = rcl_parse_arguments(argc, argv, allocator, &arguments);
  const std::string error = parsed == RCL_RET_OK ? "" : take_rcl_error();
  if (parsed == RCL_RET_OK) discard(rcl_arguments_fini(&arguments));
  if (parsed == RCL_RET_INVALID_ROS_ARGS) throw SettingsError("invalid --ros-args: " + error);
  if (parsed != RCL_RET_OK) throw JoshuaError("cannot parse arguments: " + error);
}

}  // namespace

std::string take_rcl_error() {
  std::string text = rcl_get_error_string().str;
  rcl_reset_error();
  const size_t location = text.find(", at /");  // rcl appends the source positions of its build
  return location == std::string::npos ? text : text.substr(0, location);
}

void check_rcl(rcl_ret_t ret, const std::string& what) {
  if (ret != RCL_RET_OK) throw JoshuaError(what + ": " + take_rcl_error());
}

Node::Node(int argc, char** argv, const std::string& default_name)
    : name_(default_name), notifier_(std::make_unique<Notifier>(Notifier::from_environment())) {
  rcl_allocator_t allocator = rcl_get_default_allocator();
  check_arguments(argc, argv, allocator);
  rcl_init_options_t options = rcl_get_zero_initialized_init_options();
  check_rcl(rcl_init_options_init(&options, allocator), "cannot initialise rcl");
  const rcl_ret_t init = rcl_init(argc, argv, &options, &context_);
  discard(rcl_init_options_fini(&options));
  if (init == RCL_RET_INVALID_ROS_ARGS) throw SettingsError("invalid --ros-args: " + take_rcl_error());
  check_rcl(init, "cannot initialise rcl");

  rcl_node_options_t node_options = rcl_node_get_default_options();
  const rcl_ret_t created = rcl_node_init(&node_, default_name.c_str(), "", &context_, &node_options);
  if (created == RCL_RET_NODE_INVALID_NAME || created == RCL_RET_NODE_INVALID_NAMESPACE) {
    throw SettingsError("invalid node name: " + take_rcl_error());
  }
  check_rcl(created, "cannot create node");
  name_ = rcl_node_get_name(&node_);

  rcl_params_t* overrides = nullptr;
  const rcl_ret_t parsed = rcl_arguments_get_param_overrides(&context_.global_arguments, &overrides);
  if (parsed != RCL_RET_OK) throw SettingsError("invalid parameters: " + take_rcl_error());
  parameters_ = std::make_unique<Parameters>(overrides, rcl_node_get_fully_qualified_name(&node_));

  check_rcl(rcl_guard_condition_init(&stop_guard_, &context_, rcl_guard_condition_get_default_options()),
            "cannot create a guard condition");
  stop_listener_ = std::make_unique<StopListener>([this] { discard(rcl_trigger_guard_condition(&stop_guard_)); });
}

Node::~Node() {
  stop_listener_.reset();
  if (rcl_wait_set_is_valid(&wait_set_)) discard(rcl_wait_set_fini(&wait_set_));
  if (stop_guard_.impl != nullptr) discard(rcl_guard_condition_fini(&stop_guard_));
  subscriptions_.clear();
  entities_.clear();
  parameters_.reset();
  if (rcl_node_is_valid(&node_)) discard(rcl_node_fini(&node_));
  if (rcl_context_is_valid(&context_)) discard(rcl_shutdown(&context_));
  discard(rcl_context_fini(&context_));
}

void Node::every(double period_s, std::function<void()> callback) {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s));
  timers_.push_back(Timer{period, Clock::now() + period, std::move(callback)});
}

void Node::spin() {
  check_rcl(rcl_wait_set_init(&wait_set_, subscriptions_.size(), 1, 0, 0, 0, 0, &context_,
                              rcl_get_default_allocator()),
            "cannot create a wait set");
  while (!stop_requested()) {
    notifier_->watchdog(Clock::now());
    std::optional<Clock::time_point> until = notifier_->watchdog_due();
    for (const Timer& timer : timers_) until = until ? std::min(*until, timer.next) : timer.next;
    wait_for_work(until);
    run_due_timers();
  }
  notifier_->stopping();
}

void Node::announce_ready(const std::string& detail) {
  if (ready_) return;
  ready_ = true;
  const std::string summary = (detail.empty() ? "" : detail + "; ") + serving();
  info("ready: " + summary);
  notifier_->ready(summary);
}

std::string Node::serving() const {
  std::vector<std::string> parts;
  const auto listed = [](const std::vector<std::string>& topics) {
    std::string text;
    for (const std::string& topic : std::set<std::string>(topics.begin(), topics.end())) {
      text += (text.empty() ? "" : ", ") + topic;
    }
    return text;
  };
  if (!published_.empty()) parts.push_back("publishing " + listed(published_));
  if (!subscribed_.empty()) parts.push_back("subscribing " + listed(subscribed_));
  const double rate = parameters_->get_double("rate_hz");
  if (rate != 0) {
    std::ostringstream text;
    text << "at " << rate << " Hz";  // 6 significant digits, as Python's :g
    parts.push_back(text.str());
  }
  const std::string device = parameters_->get_string("serial_port");
  if (!device.empty()) parts.push_back("on " + device);
  std::string summary;
  for (const std::string& part : parts) summary += (summary.empty() ? "" : " ") + part;
  return summary.empty() ? "no topics" : summary;
}

void Node::wait_for_work(std::optional<Clock::time_point> until) {
  check_rcl(rcl_wait_set_clear(&wait_set_), "wait set");
  for (SubscriptionBase* subscription : subscriptions_) {
    check_rcl(rcl_wait_set_add_subscription(&wait_set_, subscription->handle(), nullptr), "wait set");
  }
  check_rcl(rcl_wait_set_add_guard_condition(&wait_set_, &stop_guard_, nullptr), "wait set");
  int64_t timeout_ns = -1;  // rcl_wait blocks until something happens
  if (until) {
    const Clock::duration left = std::max(*until - Clock::now(), Clock::duration::zero());
    timeout_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
  }
  const rcl_ret_t ret = rcl_wait(&wait_set_, timeout_ns);
  if (ret == RCL_RET_TIMEOUT) return;
  check_rcl(ret, "wait failed");
  for (size_t i = 0; i < subscriptions_.size(); ++i) {
    if (wait_set_.subscriptions[i] != nullptr) subscriptions_[i]->take_all();
  }
}

void Node::run_due_timers() {
  for (Timer& timer : timers_) {
    const Clock::time_point now = Clock::now();
    if (now < timer.next) continue;
    timer.next += timer.period;
    if (timer.next <= now) timer.next = now + timer.period;
    timer.callback();
  }
}

void Node::info(const std::string& message) const { log_line("INFO", name_, message); }

void Node::warn(const std::string& message) const { log_line("WARN", name_, message); }

namespace {

[[noreturn]] void exit_process(int code) {
  // By now the node and its DDS participant are gone; the DDS libraries' static destructors would
  // still wait ~0.1 s for their threads, so the process leaves without running them.
  std::fflush(nullptr);
  std::_Exit(code);
}

}  // namespace

void run(int argc, char** argv, const std::string& default_name, Application& application) {
  std::unique_ptr<Node> node;
  std::string name = default_name;
  int code = 0;
  try {
    install_stop_handlers();
    node = std::make_unique<Node>(argc, argv, default_name);
    name = node->name();
    application.start(*node);
    if (!application.ready_later()) node->announce_ready();
    node->spin();
  } catch (const StopRequested&) {
  } catch (const JoshuaError& error) {
    std::cerr << name << ": error: " << error.what() << std::endl;
    code = error.exit_code();
  } catch (const std::exception& error) {  // a bug or an exhausted resource: still one line, exit code 1
    std::cerr << name << ": error: " << error.what() << std::endl;
    code = 1;
  }
  try {
    application.close();
  } catch (const JoshuaError& error) {
    std::cerr << name << ": error while closing: " << error.what() << std::endl;
    code = code ? code : error.exit_code();
  }
  node.reset();
  exit_process(code);
}

}  // namespace joshua
