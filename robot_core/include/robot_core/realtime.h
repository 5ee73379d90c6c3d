// Real-time scheduling for the threads that must answer at once whatever else the computer does:
// the HCL's bus loops, the HAL's device loops, and in simulation the boards' emulators and the
// simulated bus under them (on the robot, boards are microcontrollers that never wait for a
// busy PC; the emulators must not either, or a busy PC makes drivers miss their reply windows).
//
// A process sets its priority once (from its config); each such thread then calls
// enterRealtime() as it starts. Where the process may not (no CAP_SYS_NICE, RLIMIT_RTPRIO 0),
// it says so once with a WARN and runs at normal priority, as before.
#pragma once

#include <string>

namespace robot_core {

// SCHED_FIFO priority 1..99 of this process's real-time threads; 0: normal scheduling.
void setRealtimePriority(int priority);
int realtimePriority();

// The calling thread at the process's priority (nothing when it is 0), and the process's memory
// locked as it is touched (mlockall MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT, once), so that no
// page fault stalls it. False when not allowed: one WARN per process naming `role` and the cause.
bool enterRealtime(const char* role);

// The same for an explicit priority, without the WARN: true on success, else `why` says why.
bool makeThreadRealtime(int priority, std::string* why);

}  // namespace robot_core
