// The match clock as the panel shows it: counted down between two /brain/match_status messages.
#pragma once

#include <string>

namespace match_panel {

// "m:ss.d" (tenths cut, not rounded, so the clock never shows more time than is left);
// negative times show as 0:00.0.
std::string formatClock(double seconds);

// Remaining time `age` seconds after a message said `remaining`: counted down only while the
// match runs (before the start and after the end the brain's figure stands), never below 0.
double countDown(double remaining, double age, bool running);

}  // namespace match_panel
