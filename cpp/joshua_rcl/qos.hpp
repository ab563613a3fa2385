// The QoS a node's topic uses, from its qos_depth / qos_reliability / qos_durability / qos_history parameters.
#pragma once

#include "joshua_rcl/parameters.hpp"
#include "rmw/types.h"

namespace joshua {

// KEEP_ALL ignores the depth (0), as the Python runtime does. Unknown names are a SettingsError.
rmw_qos_profile_t qos_from_parameters(const Parameters& parameters);

// The QoS of /diagnostics and of a preset channel (joshua_core.servo_topics.FIXED_QOS): reliable,
// volatile, keep last 10, what diagnostic_updater, rqt and `ros2 topic pub` use.
rmw_qos_profile_t fixed_qos();

}  // namespace joshua
