#include "rtabmap_core/sim/Motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rtabmap::sim {

namespace {

constexpr double kStep = 0.01;  // metres between samples of the planned path

double signedAngle(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
}

}  // namespace

double ReferencePath::cornerRoom(size_t segment, const std::vector<double>& turn, const std::vector<bool>& pivot,
                                 const std::vector<double>& lens) const {
  // Each corner may round off half of a segment. Between two arcs turning opposite ways the plan
  // reverses its yaw rate at once; the robot's yaw rate takes maxYawRate / robotYawAcceleration
  // to follow each step, so a short straight (twice the distance covered meanwhile at full
  // speed) is kept between them: back to back, the two lags add up and the robot cuts the bend
  // by decimetres.
  const size_t a = segment, b = segment + 1;  // the segment's end vertices
  const bool arcA = a > 0 && !pivot[a] && std::fabs(turn[a]) > 1e-6;
  const bool arcB = b + 1 < turn.size() && !pivot[b] && std::fabs(turn[b]) > 1e-6;
  double straight = 0.0;
  if (arcA && arcB && turn[a] * turn[b] < 0.0) {
    const double settle = 2.0 * limits_.maxSpeed * limits_.maxYawRate / limits_.robotYawAcceleration;
    straight = std::min(settle, 0.5 * lens[segment]);
  }
  return 0.5 * (lens[segment] - straight);
}

ReferencePath::ReferencePath(const std::vector<Eigen::Vector2d>& waypoints, const MotionLimits& limits)
    : limits_(limits) {
  std::vector<Eigen::Vector2d> pts;
  for (const auto& p : waypoints) {
    if (pts.empty() || (p - pts.back()).norm() > 0.01) pts.push_back(p);
  }
  // Collinear middle points change nothing; dropping them keeps corners where they are.
  for (size_t i = 1; i + 1 < pts.size();) {
    const Eigen::Vector2d a = (pts[i] - pts[i - 1]).normalized();
    const Eigen::Vector2d b = (pts[i + 1] - pts[i]).normalized();
    if (a.dot(b) > 1.0 - 1e-9) pts.erase(pts.begin() + static_cast<std::ptrdiff_t>(i));
    else ++i;
  }
  if (pts.size() < 2) throw std::invalid_argument("ReferencePath: needs two distinct waypoints");
  if (!(limits.maxSpeed > 0 && limits.maxAcceleration > 0 && limits.maxYawRate > 0 && limits.maxYawAcceleration > 0 &&
        limits.maxLateralAcceleration > 0)) {
    throw std::invalid_argument("ReferencePath: motion limits must be > 0");
  }
  const size_t n = pts.size();
  std::vector<Eigen::Vector2d> dirs(n - 1);
  std::vector<double> lens(n - 1);
  for (size_t i = 0; i + 1 < n; ++i) {
    lens[i] = (pts[i + 1] - pts[i]).norm();
    dirs[i] = (pts[i + 1] - pts[i]) / lens[i];
  }
  // Corner at each interior vertex: the turn, whether it pivots, and its arc.
  std::vector<double> turn(n, 0.0), radius(n, 0.0), cut(n, 0.0);
  std::vector<bool> pivot(n, false);
  for (size_t i = 1; i + 1 < n; ++i) {
    turn[i] = signedAngle(dirs[i - 1], dirs[i]);
    pivot[i] = std::fabs(turn[i]) > limits.pivotAngle;
  }
  for (size_t i = 1; i + 1 < n; ++i) {
    const double a = std::fabs(turn[i]);
    if (pivot[i] || a <= 1e-6) continue;
    const double tanHalf = std::tan(0.5 * a);
    const double room = std::min(cornerRoom(i - 1, turn, pivot, lens), cornerRoom(i, turn, pivot, lens));
    radius[i] = std::min(limits.cornerRadius, room / tanHalf);
    cut[i] = radius[i] * tanHalf;
  }

  double yaw = std::atan2(dirs[0].y(), dirs[0].x());
  samples_.push_back({0.0, pts[0].x(), pts[0].y(), yaw, 0.0, 0.0, 0.0});
  appendRest(limits.dwell);
  std::vector<Sample> piece;  // geometry of the current run between stops
  auto addPoint = [&](const Eigen::Vector2d& p, double heading, double kappa) {
    if (!piece.empty()) length_ += std::hypot(p.x() - piece.back().x, p.y() - piece.back().y);
    piece.push_back({0.0, p.x(), p.y(), heading, kappa, 0.0, 0.0});
  };
  addPoint(pts[0], yaw, 0.0);
  for (size_t i = 0; i + 1 < n; ++i) {
    const Eigen::Vector2d a = pts[i] + dirs[i] * cut[i];
    const Eigen::Vector2d b = pts[i + 1] - dirs[i] * cut[i + 1];
    const double straight = (b - a).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(straight / kStep)));
    for (int k = 1; k <= steps; ++k) addPoint(a + (b - a) * (static_cast<double>(k) / steps), yaw, 0.0);
    const size_t v = i + 1;
    if (v + 1 >= n) break;
    if (pivot[v]) {
      appendTranslation(piece);
      appendTurn(pts[v].x(), pts[v].y(), yaw, turn[v]);
      yaw += turn[v];
      piece.clear();
      addPoint(pts[v], yaw, 0.0);
    } else if (radius[v] > 0.0) {
      const double r = radius[v];
      const double sign = turn[v] > 0 ? 1.0 : -1.0;
      const Eigen::Vector2d left(-dirs[i].y(), dirs[i].x());
      const Eigen::Vector2d centre = b + sign * r * left;
      const int arcSteps = std::max(2, static_cast<int>(std::ceil(r * std::fabs(turn[v]) / kStep)));
      for (int k = 1; k <= arcSteps; ++k) {
        const double phi = yaw + turn[v] * k / arcSteps;
        const Eigen::Vector2d offset = sign * r * Eigen::Vector2d(std::sin(phi), -std::cos(phi));
        addPoint(centre + offset, phi, sign / r);
      }
      yaw += turn[v];
    } else {
      yaw += turn[v];
    }
  }
  appendTranslation(piece);
  appendRest(limits.dwell);
  duration_ = samples_.back().t;
}

void ReferencePath::appendTranslation(const std::vector<Sample>& geometry) {
  const size_t n = geometry.size();
  if (n < 2) return;
  std::vector<double> ds(n, 0.0), vmax(n), v(n);
  for (size_t i = 1; i < n; ++i) ds[i] = std::hypot(geometry[i].x - geometry[i - 1].x, geometry[i].y - geometry[i - 1].y);
  for (size_t i = 0; i < n; ++i) {
    const double k = std::fabs(geometry[i].kappa);
    vmax[i] = limits_.maxSpeed;
    if (k > 1e-9) vmax[i] = std::min({vmax[i], limits_.maxYawRate / k, std::sqrt(limits_.maxLateralAcceleration / k)});
  }
  // Stopped at both ends; accelerate forward, brake backward.
  v[0] = 0.0;
  for (size_t i = 1; i < n; ++i) v[i] = std::min(vmax[i], std::sqrt(v[i - 1] * v[i - 1] + 2.0 * limits_.maxAcceleration * ds[i]));
  v[n - 1] = 0.0;
  for (size_t i = n - 1; i-- > 0;) v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2.0 * limits_.maxAcceleration * ds[i + 1]));
  double t = samples_.back().t;
  for (size_t i = 1; i < n; ++i) {
    const double sum = v[i - 1] + v[i];
    t += sum > 1e-12 ? 2.0 * ds[i] / sum : std::sqrt(2.0 * ds[i] / limits_.maxAcceleration);
    Sample s = geometry[i];
    s.t = t;
    s.v = v[i];
    s.omega = v[i] * geometry[i].kappa;
    samples_.push_back(s);
  }
}

void ReferencePath::appendTurn(double x, double y, double yaw0, double angle) {
  // Trapezoidal yaw-rate profile (triangular for short turns).
  const double a = std::fabs(angle);
  const double sign = angle >= 0 ? 1.0 : -1.0;
  const double w = limits_.maxYawRate;
  const double alpha = limits_.maxYawAcceleration;
  double tAcc = w / alpha;
  double peak = w;
  double tCruise = (a - w * w / alpha) / w;
  if (tCruise < 0.0) {
    tAcc = std::sqrt(a / alpha);
    peak = alpha * tAcc;
    tCruise = 0.0;
  }
  const double total = 2.0 * tAcc + tCruise;
  const double t0 = samples_.back().t;
  const int steps = std::max(2, static_cast<int>(std::ceil(total / 0.005)));
  for (int k = 1; k <= steps; ++k) {
    const double t = total * k / steps;
    double done, rate;
    if (t < tAcc) {
      rate = alpha * t;
      done = 0.5 * alpha * t * t;
    } else if (t < tAcc + tCruise) {
      rate = peak;
      done = 0.5 * alpha * tAcc * tAcc + peak * (t - tAcc);
    } else {
      const double td = total - t;
      rate = alpha * td;
      done = a - 0.5 * alpha * td * td;
    }
    samples_.push_back({t0 + t, x, y, yaw0 + sign * done, 0.0, 0.0, sign * rate});
  }
}

void ReferencePath::appendRest(double seconds) {
  if (seconds <= 0.0) return;
  Sample s = samples_.back();
  s.t += seconds;
  s.v = 0.0;
  s.omega = 0.0;
  s.kappa = 0.0;
  samples_.push_back(s);
}

ReferenceState ReferencePath::at(double t) const {
  ReferenceState r;
  if (t <= samples_.front().t) {
    const Sample& s = samples_.front();
    r.x = s.x;
    r.y = s.y;
    r.yaw = s.yaw;
    return r;
  }
  if (t >= samples_.back().t) {
    const Sample& s = samples_.back();
    r.x = s.x;
    r.y = s.y;
    r.yaw = s.yaw;
    return r;
  }
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), t, [](double v, const Sample& s) { return v < s.t; });
  const Sample& b = *it;
  const Sample& a = *(it - 1);
  const double u = b.t > a.t ? (t - a.t) / (b.t - a.t) : 1.0;
  r.x = a.x + u * (b.x - a.x);
  r.y = a.y + u * (b.y - a.y);
  r.yaw = a.yaw + u * (b.yaw - a.yaw);
  r.v = a.v + u * (b.v - a.v);
  r.omega = a.omega + u * (b.omega - a.omega);
  return r;
}

RobotSimulator::RobotSimulator(const ReferencePath& path, double step) : path_(path), dt_(step) {
  const ReferenceState start = path.at(0.0);
  state_.pose = {start.x, start.y, Pose2::normalizeAngle(start.yaw)};
  yawUnwrapped_ = start.yaw;
}

const RobotState& RobotSimulator::step() {
  const MotionLimits& lim = path_.limits();
  const ReferenceState ref = path_.at(state_.t);
  const double c = std::cos(yawUnwrapped_);
  const double s = std::sin(yawUnwrapped_);
  const double dx = ref.x - state_.pose.x;
  const double dy = ref.y - state_.pose.y;
  const double ex = c * dx + s * dy;   // pose error in the robot frame
  const double ey = -s * dx + c * dy;
  const double eyaw = ref.yaw - yawUnwrapped_;
  // Feedforward of the plan plus feedback (gains chosen for centimetre tracking at 0.5 m/s
  // without oscillation under the acceleration limits).
  const double kx = 2.0, ky = 8.0, kyaw = 3.0, kyawStill = 3.0;
  double vCmd = ref.v * std::cos(eyaw) + kx * ex;
  double wCmd = ref.omega + ref.v * (ky * ey + kyaw * std::sin(eyaw)) + kyawStill * std::sin(eyaw);
  vCmd = std::clamp(vCmd, -1.5 * lim.maxSpeed, 1.5 * lim.maxSpeed);
  wCmd = std::clamp(wCmd, -1.5 * lim.maxYawRate, 1.5 * lim.maxYawRate);
  const double dv = std::clamp(vCmd - state_.v, -lim.robotAcceleration * dt_, lim.robotAcceleration * dt_);
  const double dw = std::clamp(wCmd - state_.omega, -lim.robotYawAcceleration * dt_, lim.robotYawAcceleration * dt_);
  const double v = state_.v + dv;
  const double w = state_.omega + dw;
  // Exact unicycle motion over the step with constant v and w.
  const double dyaw = w * dt_;
  double fx, fy;
  if (std::fabs(dyaw) > 1e-12) {
    fx = v / w * std::sin(dyaw);
    fy = v / w * (1.0 - std::cos(dyaw));
  } else {
    fx = v * dt_;
    fy = 0.0;
  }
  state_.pose.x += c * fx - s * fy;
  state_.pose.y += s * fx + c * fy;
  yawUnwrapped_ += dyaw;
  state_.pose.yaw = Pose2::normalizeAngle(yawUnwrapped_);
  state_.v = v;
  state_.omega = w;
  state_.acceleration = dv / dt_;
  state_.t = static_cast<double>(++steps_) * dt_;
  return state_;
}

}  // namespace rtabmap::sim
