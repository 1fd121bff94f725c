#pragma once
// edx's discrete-event engine in one include: time and clocks, the simulator and its processes,
// events, resources, FIFOs, statistics and the timeline. See docs/SIM_CORE.md.
#include "sim_core/clock.hpp"
#include "sim_core/event.hpp"
#include "sim_core/event_queue.hpp"
#include "sim_core/fifo.hpp"
#include "sim_core/process.hpp"
#include "sim_core/resource.hpp"
#include "sim_core/simulator.hpp"
#include "sim_core/stats.hpp"
#include "sim_core/time.hpp"
#include "sim_core/timeline.hpp"
