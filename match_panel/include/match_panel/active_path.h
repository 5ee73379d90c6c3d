// The brain's active state path and its last trigger, from the smach introspection
// (/brain/smach/container_status, one message per container and transition).
#pragma once

#include <map>
#include <string>
#include <vector>

namespace match_panel {

class ActivePath {
 public:
  // One container's status: its path ('/ROOT', '/ROOT/CHILD') and its active states.
  // A Supervisor root (initial state BODY) runs BODY, or a trigger's handler under that
  // trigger's name: its last non-BODY active state is the last trigger fired.
  void update(const std::string& path, const std::vector<std::string>& initial_states,
              const std::vector<std::string>& active_states);

  // The root's path for a strategy: the brain publishes it as '/' + name.upper().
  static std::string rootFor(const std::string& strategy);

  // The running strategy's root: rootFor(strategy) once seen, else the root container
  // ('/X') heard from last. A strategy that delegates (match runs match2009) publishes its
  // delegate's root, and an old strategy's root stops being published after a switch.
  std::string currentRoot(const std::string& strategy) const;

  // Root, then each active state down into its container while that container is known:
  // "/MATCH_2009/BODY/MOVE". Empty when the root was never seen.
  std::string path(const std::string& root) const;

  // The last trigger the root ran (kept after it returns to BODY); empty when none yet.
  std::string lastTrigger(const std::string& root) const;

  void clear();

 private:
  std::map<std::string, std::vector<std::string>> active_;  // container path -> active states
  std::map<std::string, std::string> last_trigger_;         // root path -> last trigger
  std::string last_root_;                                   // the root container heard from last
};

}  // namespace match_panel
