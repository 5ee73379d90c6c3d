#include "match_panel/active_path.h"

#include <cctype>
#include <set>

namespace match_panel {

void ActivePath::update(const std::string& path, const std::vector<std::string>& initial_states,
                        const std::vector<std::string>& active_states) {
  active_[path] = active_states;
  if (path.size() > 1 && path[0] == '/' && path.find('/', 1) == std::string::npos) last_root_ = path;
  // Only a Supervisor's states are BODY and triggers; another container's are plain states.
  const bool supervisor = initial_states.size() == 1 && initial_states[0] == "BODY";
  if (supervisor && !active_states.empty() && active_states[0] != "BODY") last_trigger_[path] = active_states[0];
}

std::string ActivePath::rootFor(const std::string& strategy) {
  std::string root = "/";
  for (char c : strategy) root += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return root;
}

std::string ActivePath::currentRoot(const std::string& strategy) const {
  const std::string root = rootFor(strategy);
  return active_.count(root) ? root : last_root_;
}

std::string ActivePath::path(const std::string& root) const {
  auto it = active_.find(root);
  if (it == active_.end()) return "";
  std::string result = root;
  std::set<std::string> seen;  // a malformed path pointing back at itself ends the walk
  while (it != active_.end() && !it->second.empty() && seen.insert(it->first).second) {
    // Concurrent containers have several active states: the first one is followed.
    result = it->first + "/" + it->second.front();
    it = active_.find(result);
  }
  return result;
}

std::string ActivePath::lastTrigger(const std::string& root) const {
  auto it = last_trigger_.find(root);
  return it == last_trigger_.end() ? "" : it->second;
}

void ActivePath::clear() {
  active_.clear();
  last_trigger_.clear();
  last_root_.clear();
}

}  // namespace match_panel
