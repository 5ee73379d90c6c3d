#include "hcl_drivers/board_check.h"

#include "hcl_drivers/board.h"

namespace hcl_drivers {

const char* toString(CheckLevel level) {
  switch (level) {
    case CheckLevel::kOk: return "OK";
    case CheckLevel::kWarn: return "WARN";
    case CheckLevel::kFail: return "FAIL";
  }
  return "?";
}

void CheckReport::ok(const std::string& item, const std::string& expected, const std::string& found) {
  rows_.push_back({board_, item, expected, found, CheckLevel::kOk, ""});
}

void CheckReport::warn(const std::string& item, const std::string& expected, const std::string& found,
                       const std::string& hint) {
  rows_.push_back({board_, item, expected, found, CheckLevel::kWarn, hint});
}

void CheckReport::fail(const std::string& item, const std::string& expected, const std::string& found,
                       const std::string& hint) {
  rows_.push_back({board_, item, expected, found, CheckLevel::kFail, hint});
}

void Board::check(BoardContext& /*ctx*/, CheckReport& report) {
  report.warn("check", "a doctor check", "none for this board type",
              "the board type has no check() yet: watch its /diagnostics under roslaunch");
}

}  // namespace hcl_drivers
