#include "robot_sim/world/game.h"

#include <algorithm>
#include <cmath>

namespace robot_sim {

Game::Game(const WorldConfig& config)
    : table_(config.table),
      match_(config.match),
      opponent_enabled_(config.opponent.enabled),
      elements_(config.table.elements) {
  for (const auto& [name, c] : config.robot.collectors) collectors_[name].config = c;
  scoring_.assign(elements_.size(), Scoring{});
}

bool Game::kindOk(const std::vector<std::string>& kinds, const GameElement& e) const {
  return kinds.empty() || std::find(kinds.begin(), kinds.end(), e.kind) != kinds.end();
}

// A gripper (the 2009 hand) takes the nearest matching element at its mouth when its fingers
// close, carries it, and puts it down at the mouth when a finger opens. The lift's height is
// not modelled: a released element stands on the table (no stacking).
void Game::stepGripper(Collector& c, const RobotBody& ours, const std::map<std::string, ServoState>& servos) {
  bool closed = true;
  for (std::size_t i = 0; i < c.config.fingers.size(); ++i)
    closed = closed && std::abs(servos.at(c.config.fingers[i]).position - c.config.finger_closed[i]) <= c.config.finger_tolerance;
  const Pose2D mouth = ours.toMap(c.config.x, c.config.y);
  if (!closed) {
    for (std::size_t i : c.gripped) {
      GameElement& e = elements_[i];
      e.carried = false;
      e.carrier = Mover::nobody;
      e.moved_by = Mover::ours;
      e.pose.x = mouth.x;
      e.pose.y = mouth.y;
    }
    c.gripped.clear();
    c.held = 0;
    c.was_closed = false;
    return;
  }
  if (c.was_closed) return;  // fingers closed on nothing stay empty until they open again
  c.was_closed = true;
  int best = -1;
  double best_d = c.config.radius;
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    const GameElement& e = elements_[i];
    const double d = std::hypot(e.pose.x - mouth.x, e.pose.y - mouth.y);
    if (!e.carried && kindOk(c.config.kinds, e) && d <= best_d) {
      best = static_cast<int>(i);
      best_d = d;
    }
  }
  if (best >= 0 && c.held < c.config.capacity) {
    GameElement& e = elements_[best];
    e.carried = true;
    e.carrier = e.moved_by = Mover::ours;
    c.gripped.push_back(static_cast<std::size_t>(best));
    ++c.held;
  }
}

// A collector swallows matching elements at its mouth while its motor runs forward and spits
// one out ahead every 0.25 s while it runs backward.
void Game::stepCollector(Collector& c, double dt, const RobotBody& ours) {
  const MotorState* motor = ours.motor(c.config.motor);
  const double cmd = motor ? motor->command : 0.0;
  const Pose2D mouth = ours.toMap(c.config.x, c.config.y);
  c.eject_cooldown = std::max(0.0, c.eject_cooldown - dt);
  for (auto& in : c.entering) in.second -= dt;  // on their way in
  c.entering.erase(std::remove_if(c.entering.begin(), c.entering.end(), [](const auto& in) { return in.second <= 0.0; }),
                   c.entering.end());
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    GameElement& e = elements_[i];
    const bool kind_ok = kindOk(c.config.kinds, e);
    const bool entering = std::any_of(c.entering.begin(), c.entering.end(), [&](const auto& in) { return in.first == i; });
    if (cmd > 0.1 && !e.carried && kind_ok && c.held < c.config.capacity &&
        std::hypot(e.pose.x - mouth.x, e.pose.y - mouth.y) <= c.config.radius) {
      e.carried = true;
      e.carrier = e.moved_by = Mover::ours;
      ++c.held;
      if (c.config.intake_time > 0.0) c.entering.emplace_back(i, c.config.intake_time);
    } else if (cmd < -0.1 && e.carried && e.carrier == Mover::ours && !entering && c.held > 0 &&
               c.eject_cooldown <= 0.0 && kind_ok) {
      e.carried = false;
      e.carrier = Mover::nobody;
      e.moved_by = Mover::ours;
      e.pose = ours.toMap(c.config.x + c.config.radius + e.radius, c.config.y);
      --c.held;
      c.eject_cooldown = 0.25;
    }
  }
}

void Game::stepElements(double dt, const RobotBody& ours, const std::map<std::string, ServoState>& servos,
                        const std::optional<Circle>& opponent) {
  for (auto& kv : collectors_) {
    if (kv.second.config.fingers.empty())
      stepCollector(kv.second, dt, ours);
    else
      stepGripper(kv.second, ours, servos);
  }
  // Carried elements ride along (a gripper's in its mouth, a collector's inside the robot);
  // loose ones are pushed out of our outline (along its normal at the contact) and of the
  // opponent's circle, and stay on the table.
  const Pose2D& pose = ours.pose();
  const double reach = ours.footprint().boundingRadius();
  for (const auto& kv : collectors_) {
    const Pose2D mouth = ours.toMap(kv.second.config.x, kv.second.config.y);
    std::vector<std::size_t> at_mouth = kv.second.gripped;
    for (const auto& in : kv.second.entering) at_mouth.push_back(in.first);
    for (std::size_t i : at_mouth) {
      elements_[i].pose.x = mouth.x;
      elements_[i].pose.y = mouth.y;
    }
  }
  for (auto& e : elements_) {
    if (e.carried) {
      const bool by_opponent = e.carrier == Mover::opponent && opponent;
      const bool gripped = e.carrier == Mover::ours && isGripped(e);
      if (!gripped) {
        e.pose.x = by_opponent ? opponent->x : pose.x;
        e.pose.y = by_opponent ? opponent->y : pose.y;
      }
      continue;
    }
    if (std::hypot(e.pose.x - pose.x, e.pose.y - pose.y) < reach + e.radius) {
      Circle c{e.pose.x, e.pose.y, e.radius};
      if (ours.placed().pushOut(c)) {
        e.pose.x = c.x;
        e.pose.y = c.y;
        e.moved_by = Mover::ours;
      }
    }
    if (opponent) {
      const double dx = e.pose.x - opponent->x, dy = e.pose.y - opponent->y;
      const double d = std::hypot(dx, dy);
      const double need = opponent->r + e.radius;
      if (d < need) {
        const double ux = d > 1e-9 ? dx / d : 1.0, uy = d > 1e-9 ? dy / d : 0.0;
        e.pose.x = opponent->x + ux * need;
        e.pose.y = opponent->y + uy * need;
        e.moved_by = Mover::opponent;
      }
    }
    e.pose.x = std::clamp(e.pose.x, e.radius, table_.length - e.radius);
    e.pose.y = std::clamp(e.pose.y, e.radius, table_.width - e.radius);
  }
}

bool Game::isGripped(const GameElement& e) const {
  for (const auto& kv : collectors_) {
    for (std::size_t i : kv.second.gripped)
      if (&elements_[i] == &e) return true;
    for (const auto& in : kv.second.entering)
      if (&elements_[in.first] == &e) return true;
  }
  return false;
}

bool Game::takeByOpponent(std::size_t i) {
  if (i >= elements_.size() || elements_[i].carried) return false;
  elements_[i].carried = true;
  elements_[i].carrier = elements_[i].moved_by = Mover::opponent;
  return true;
}

void Game::putDownByOpponent(std::size_t i, double x, double y) {
  if (i >= elements_.size() || elements_[i].carrier != Mover::opponent) return;
  GameElement& e = elements_[i];
  e.carried = false;
  e.carrier = Mover::nobody;
  e.moved_by = Mover::opponent;
  e.pose.x = std::clamp(x, e.radius, table_.length - e.radius);
  e.pose.y = std::clamp(y, e.radius, table_.width - e.radius);
}

// ---------------------------------------------------------------- the referee
// A zone with a team colour scores for the team of that colour; a "placer" zone for the robot
// that last moved the element (nobody's points for an element nobody touched).
Mover Game::zoneTeam(const Zone& zone, const GameElement& e) const {
  if (zone.team.empty() || zone.team == "placer") return e.moved_by;
  if (zone.team == colour_ours_) return Mover::ours;
  if (zone.team == colour_opponent_) return Mover::opponent;
  return Mover::nobody;
}

void Game::begin(double time, const Pose2D& ours, const std::optional<Pose2D>& opponent) {
  started_ = true;
  start_time_ = time;
  scoring_.assign(elements_.size(), Scoring{});
  for (const Zone& z : table_.start_zones)
    if (colour_ours_.empty() && z.contains(ours.x, ours.y)) colour_ours_ = z.name;
  if (opponent)
    for (const Zone& z : table_.start_zones)
      if (z.name != colour_ours_ && z.contains(opponent->x, opponent->y)) colour_opponent_ = z.name;
  for (const Zone& z : table_.start_zones)
    if (colour_opponent_.empty() && z.name != colour_ours_) colour_opponent_ = z.name;
}

void Game::referee(double time) {
  if (!started_ || over_) return;
  const double t = time - start_time_;
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    const GameElement& e = elements_[i];
    Scoring now;
    if (!e.carried) {
      for (std::size_t z = 0; z < table_.score_zones.size(); ++z) {
        const Zone& zone = table_.score_zones[z];
        if (kindOk(zone.kinds, e) && zone.contains(e.pose.x, e.pose.y)) {
          now.zone = static_cast<int>(z);
          now.team = zoneTeam(zone, e);
          break;
        }
      }
      if (now.team == Mover::nobody) now.zone = -1;  // lies there for nobody: no points, no event
    }
    Scoring& was = scoring_[i];
    if (now.zone == was.zone && now.team == was.team) continue;
    const std::string name = e.kind + "#" + std::to_string(i);
    if (was.zone >= 0) {
      const Zone& z = table_.score_zones[was.zone];
      events_.push_back(RefereeEvent{t, name, z.name, -z.points, was.team});
    }
    if (now.zone >= 0) {
      const Zone& z = table_.score_zones[now.zone];
      events_.push_back(RefereeEvent{t, name, z.name, z.points, now.team});
    }
    was = now;
  }
  if (t >= match_.duration) over_ = true;  // the score freezes
}

MatchProgress Game::progress(double time) const {
  MatchProgress m;
  m.started = started_;
  m.elapsed = started_ ? std::min(time - start_time_, match_.duration) : 0.0;
  m.remaining = match_.duration - m.elapsed;
  m.over = over_;
  for (const Scoring& s : scoring_) {
    if (s.zone < 0) continue;
    const int points = table_.score_zones[s.zone].points;
    if (s.team == Mover::ours) m.score_ours += points;
    if (s.team == Mover::opponent) m.score_opponent += points;
  }
  m.colour_ours = colour_ours_;
  m.colour_opponent = colour_opponent_;
  return m;
}

}  // namespace robot_sim
