#include "robot_sim/world/ros_world_io.h"

#include <cmath>

#include "robot_sim/world/footprint.h"

namespace robot_sim {

WorldConfig loadWorldConfig(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) {
  XmlRpc::XmlRpcValue world, table, robot;
  pnh.getParam("world", world);  // missing: every default (the schema has one for each)
  nh.getParam("table", table);
  nh.getParam("robot", robot);  // the robot as built: the simulated robot's geometry
  // One match length for the robot and the referee: the brain's, unless the world sets its own.
  XmlRpc::XmlRpcValue brain_duration;
  if (nh.getParam("brain/match/duration", brain_duration) && world.getType() != XmlRpc::XmlRpcValue::TypeInvalid &&
      !(world.hasMember("match") && world["match"].hasMember("duration")))
    world["match"]["duration"] = brain_duration;
  return parseWorldConfig(world, pnh.resolveName("world"), table, nh.resolveName("table"), robot,
                          nh.resolveName("robot"));
}

namespace {
geometry_msgs::Quaternion yaw(double theta) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(0.5 * theta);
  q.w = std::cos(0.5 * theta);
  return q;
}

visualization_msgs::Marker marker(const std::string& ns, int id, int type, const ros::Time& stamp, double r, double g,
                                  double b, double a = 1.0) {
  visualization_msgs::Marker m;
  m.header.frame_id = "map";
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.color.r = static_cast<float>(r);
  m.color.g = static_cast<float>(g);
  m.color.b = static_cast<float>(b);
  m.color.a = static_cast<float>(a);
  return m;
}

void elementColour(const std::string& kind, double& r, double& g, double& b) {
  r = g = b = 0.8;
  if (kind.find("red") != std::string::npos) r = 0.9, g = 0.1, b = 0.1;
  else if (kind.find("blue") != std::string::npos) r = 0.1, g = 0.3, b = 0.9;
  else if (kind.find("green") != std::string::npos) r = 0.1, g = 0.7, b = 0.2;
  else if (kind.find("white") != std::string::npos) r = g = b = 0.95;
  else if (kind.find("column") != std::string::npos) r = 0.95, g = 0.85, b = 0.55;
}
}  // namespace

nav_msgs::Odometry toOdometry(const BodyTruth& t, const ros::Time& stamp, const std::string& child_frame) {
  nav_msgs::Odometry o;
  o.header.stamp = stamp;
  o.header.frame_id = "map";
  o.child_frame_id = child_frame;
  o.pose.pose.position.x = t.pose.x;
  o.pose.pose.position.y = t.pose.y;
  o.pose.pose.orientation = yaw(t.pose.theta);
  o.twist.twist.linear.x = t.v;
  o.twist.twist.angular.z = t.w;
  return o;
}

GameElements toElementsMsg(const std::vector<GameElement>& elements, const ros::Time& stamp) {
  GameElements m;
  m.header.stamp = stamp;
  m.header.frame_id = "map";
  for (const auto& e : elements) {
    GameElementState s;
    s.kind = e.kind;
    s.pose.x = e.pose.x;
    s.pose.y = e.pose.y;
    s.pose.theta = e.pose.theta;
    s.radius = e.radius;
    s.height = e.height;
    s.carried = e.carried;
    m.elements.push_back(s);
  }
  return m;
}

robot_sim::MatchState toMatchMsg(const MatchProgress& p, const std::string& year, const ros::Time& stamp) {
  robot_sim::MatchState m;
  m.header.stamp = stamp;
  m.year = year;
  m.started = p.started;
  m.over = p.over;
  m.elapsed = p.elapsed;
  m.remaining = p.remaining;
  m.score = p.score_ours;
  m.score_ours = p.score_ours;
  m.score_opponent = p.score_opponent;
  m.colour_ours = p.colour_ours;
  m.colour_opponent = p.colour_opponent;
  return m;
}

robot_sim::ScoreEvents toScoreEventsMsg(const std::vector<RefereeEvent>& events, const ros::Time& stamp) {
  robot_sim::ScoreEvents out;
  out.header.stamp = stamp;
  for (const RefereeEvent& e : events) {
    robot_sim::ScoreEvent m;
    m.time = e.time;
    m.element = e.element;
    m.zone = e.zone;
    m.points = e.points;
    m.team = e.team == Mover::ours ? "ours" : e.team == Mover::opponent ? "opponent" : "nobody";
    out.events.push_back(m);
  }
  return out;
}

visualization_msgs::MarkerArray worldMarkers(const WorldConfig& c, const WorldSnapshot& s, const ros::Time& stamp) {
  using visualization_msgs::Marker;
  visualization_msgs::MarkerArray out;
  const double L = c.table.length, W = c.table.width, H = c.table.border_height, T = 0.022;
  Marker table = marker("table", 0, Marker::CUBE, stamp, 0.2, 0.45, 0.75);
  table.pose.position.x = L / 2;
  table.pose.position.y = W / 2;
  table.pose.position.z = -0.005;
  table.scale.x = L;
  table.scale.y = W;
  table.scale.z = 0.01;
  out.markers.push_back(table);
  const double bx[4] = {L / 2, L / 2, -T / 2, L + T / 2}, by[4] = {-T / 2, W + T / 2, W / 2, W / 2};
  const double sx[4] = {L + 2 * T, L + 2 * T, T, T}, sy[4] = {T, T, W, W};
  for (int i = 0; i < 4; ++i) {
    Marker b = marker("borders", i, Marker::CUBE, stamp, 0.95, 0.95, 0.95);
    b.pose.position.x = bx[i];
    b.pose.position.y = by[i];
    b.pose.position.z = H / 2;
    b.scale.x = sx[i];
    b.scale.y = sy[i];
    b.scale.z = H;
    out.markers.push_back(b);
  }
  for (std::size_t i = 0; i < c.table.beacons.size(); ++i) {
    Marker b = marker("beacons", static_cast<int>(i), Marker::CYLINDER, stamp, 0.1, 0.1, 0.1);
    b.pose.position.x = c.table.beacons[i].x;
    b.pose.position.y = c.table.beacons[i].y;
    b.pose.position.z = 0.2;
    b.scale.x = b.scale.y = 0.08;
    b.scale.z = 0.4;
    out.markers.push_back(b);
  }
  int id = 0;
  for (const auto* zones : {&c.table.start_zones, &c.table.score_zones}) {
    for (const Zone& z : *zones) {
      const bool start = zones == &c.table.start_zones;
      Marker m = marker(start ? "start_zones" : "score_zones", id++, Marker::CUBE, stamp, start ? 0.9 : 0.2,
                        start ? 0.8 : 0.8, 0.2, 0.5);
      m.pose.position.x = 0.5 * (z.x0 + z.x1);
      m.pose.position.y = 0.5 * (z.y0 + z.y1);
      m.pose.position.z = 0.001;
      m.scale.x = std::max(0.001, z.x1 - z.x0);
      m.scale.y = std::max(0.001, z.y1 - z.y0);
      m.scale.z = 0.002;
      out.markers.push_back(m);
    }
  }
  // Our robot's outline at its true pose: the collision shape, which the URDF's chassis only
  // approximates when sim/world/robot/footprint is configured.
  Marker outline = marker("footprint", 0, Marker::LINE_STRIP, stamp, 0.0, 0.0, 0.0);
  outline.scale.x = 0.006;
  for (const Point2D& p : robotFootprint(c.robot).placed(s.robot)) {
    geometry_msgs::Point q;
    q.x = p.x;
    q.y = p.y;
    q.z = 0.01;
    outline.points.push_back(q);
  }
  outline.points.push_back(outline.points.front());
  out.markers.push_back(outline);
  if (s.opponent_radius > 0.0) {
    Marker o = marker("opponent", 0, Marker::CYLINDER, stamp, 0.8, 0.2, 0.8, 0.9);
    o.pose.position.x = s.opponent.x;
    o.pose.position.y = s.opponent.y;
    o.pose.position.z = 0.175;
    o.pose.orientation = yaw(s.opponent.theta);
    o.scale.x = o.scale.y = 2 * s.opponent_radius;
    o.scale.z = 0.35;
    out.markers.push_back(o);
    Marker h = marker("opponent", 1, Marker::ARROW, stamp, 1.0, 1.0, 1.0);
    h.pose = o.pose;
    h.pose.position.z = 0.36;
    h.scale.x = s.opponent_radius;
    h.scale.y = h.scale.z = 0.03;
    out.markers.push_back(h);
  }
  for (std::size_t i = 0; i < s.elements.size(); ++i) {
    const GameElement& e = s.elements[i];
    const bool ball = e.kind.rfind("ball", 0) == 0;
    double r, g, b;
    elementColour(e.kind, r, g, b);
    Marker m = marker("elements", static_cast<int>(i), ball ? Marker::SPHERE : Marker::CYLINDER, stamp, r, g, b);
    m.pose.position.x = e.pose.x;
    m.pose.position.y = e.pose.y;
    m.pose.position.z = (e.carried ? 0.2 : 0.0) + e.height / 2;
    m.scale.x = m.scale.y = 2 * e.radius;
    m.scale.z = ball ? 2 * e.radius : e.height;
    out.markers.push_back(m);
  }
  return out;
}

}  // namespace robot_sim
