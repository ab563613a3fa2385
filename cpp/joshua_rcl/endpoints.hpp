// Typed publishers and subscriptions over rcl, for C++ message types (rosidl_typesupport_cpp).
#pragma once

#include <functional>
#include <string>

#include "joshua_rcl/errors.hpp"
#include "rcl/error_handling.h"
#include "rcl/publisher.h"
#include "rcl/subscription.h"
#include "rosidl_typesupport_cpp/message_type_support.hpp"

namespace joshua {

// rcl's last error message, cleared (rcl keeps one per thread).
std::string take_rcl_error();

// Throws JoshuaError("<what>: <rcl error>") unless `ret` is RCL_RET_OK.
void check_rcl(rcl_ret_t ret, const std::string& what);

// Ignores the result of a finalisation: at tear-down there is nothing left to do about a failure.
inline void discard(rcl_ret_t) { rcl_reset_error(); }

// Anything the node finalises before itself.
class Entity {
 public:
  virtual ~Entity() = default;
};

template <class Message>
class Publisher : public Entity {
 public:
  Publisher(rcl_node_t* node, const std::string& topic, const rmw_qos_profile_t& qos) : node_(node) {
    rcl_publisher_options_t options = rcl_publisher_get_default_options();
    options.qos = qos;
    const auto* type = rosidl_typesupport_cpp::get_message_type_support_handle<Message>();
    check_rcl(rcl_publisher_init(&publisher_, node_, type, topic.c_str(), &options),
              "cannot create a publisher on " + topic);
  }
  ~Publisher() override { discard(rcl_publisher_fini(&publisher_, node_)); }
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  void publish(const Message& message) { check_rcl(rcl_publish(&publisher_, &message, nullptr), "publish failed"); }

 private:
  rcl_node_t* node_;
  rcl_publisher_t publisher_ = rcl_get_zero_initialized_publisher();
};

// What the wait loop needs of a subscription: its rcl handle and a way to deliver what arrived.
class SubscriptionBase : public Entity {
 public:
  virtual rcl_subscription_t* handle() = 0;
  virtual void take_all() = 0;
};

template <class Message>
class Subscription : public SubscriptionBase {
 public:
  using Callback = std::function<void(const Message&)>;

  Subscription(rcl_node_t* node, const std::string& topic, const rmw_qos_profile_t& qos, Callback callback)
      : node_(node), callback_(std::move(callback)) {
    rcl_subscription_options_t options = rcl_subscription_get_default_options();
    options.qos = qos;
    const auto* type = rosidl_typesupport_cpp::get_message_type_support_handle<Message>();
    check_rcl(rcl_subscription_init(&subscription_, node_, type, topic.c_str(), &options),
              "cannot subscribe to " + topic);
  }
  ~Subscription() override { discard(rcl_subscription_fini(&subscription_, node_)); }
  Subscription(const Subscription&) = delete;
  Subscription& operator=(const Subscription&) = delete;

  rcl_subscription_t* handle() override { return &subscription_; }

  void take_all() override {
    rmw_message_info_t info = rmw_get_zero_initialized_message_info();
    while (true) {
      const rcl_ret_t ret = rcl_take(&subscription_, &message_, &info, nullptr);
      if (ret == RCL_RET_SUBSCRIPTION_TAKE_FAILED) return;
      check_rcl(ret, "take failed");
      callback_(message_);
    }
  }

 private:
  rcl_node_t* node_;
  rcl_subscription_t subscription_ = rcl_get_zero_initialized_subscription();
  Callback callback_;
  Message message_;
};

}  // namespace joshua
