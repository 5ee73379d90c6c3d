// What the hardware doctor (`rosrun hcl_drivers doctor ROBOT`) learns about one board: rows of
// "checked item, expected, found, OK/WARN/FAIL, hint for the fix". Each board type fills it in
// its Board::check() (board.h), next to its driver; bus-wide checks (a CAN node or I2C chip
// nobody configured, bus load) read the channel the board declares here.
#pragma once

#include <string>
#include <vector>

namespace hcl_drivers {

enum class CheckLevel { kOk, kWarn, kFail };
const char* toString(CheckLevel level);  // "OK", "WARN", "FAIL"

struct CheckRow {
  std::string board;     // the board block's name, e.g. "motor_board"
  std::string item;      // what was checked: "node", "identity", "heartbeat", "frames", ...
  std::string expected;  // from the configuration
  std::string found;     // on the channel
  CheckLevel level = CheckLevel::kOk;
  std::string hint;      // how to fix it (empty when OK)
};

// Where a board lives, for the bus-wide checks: kind "can" (bus URL, node id), "i2c" (bus,
// 7-bit address) or "" (a channel of its own: serial port, joystick, camera).
struct BoardChannel {
  std::string kind;
  std::string bus;
  int address = -1;
  bool answered = false;  // the board answered at its configured address
};

class CheckReport {
 public:
  explicit CheckReport(std::string board) : board_(std::move(board)) {}
  void ok(const std::string& item, const std::string& expected, const std::string& found);
  void warn(const std::string& item, const std::string& expected, const std::string& found, const std::string& hint);
  void fail(const std::string& item, const std::string& expected, const std::string& found, const std::string& hint);
  void add(CheckRow row) { rows_.push_back(std::move(row)); }
  const std::string& board() const { return board_; }
  const std::vector<CheckRow>& rows() const { return rows_; }
  std::vector<CheckRow>& rows() { return rows_; }
  BoardChannel channel;

 private:
  std::string board_;
  std::vector<CheckRow> rows_;
};

}  // namespace hcl_drivers
