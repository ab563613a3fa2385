// SIGINT/SIGTERM handling: the handler only records the request; loops poll it.
#pragma once

namespace joshua {

// Install the SIGINT and SIGTERM handlers (once, before rcl starts).
void install_stop_handlers();

// True once SIGINT or SIGTERM has arrived.
bool stop_requested();

// Throws StopRequested when a stop has been requested (for long start-up steps).
void throw_if_stopping();

}  // namespace joshua
