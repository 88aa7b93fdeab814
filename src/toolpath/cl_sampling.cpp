#include "cwe/toolpath/cl_sampling.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cwe/geometry/tolerance.hpp"

namespace cwe {

double default_cl_step(double tool_diameter) { return std::min(0.5, tool_diameter / 20.0); }

ClSampler::ClSampler(const SamplingOptions& options) : options_(options) {
  if (!(options.step > 0.0) || !std::isfinite(options.step)) {
    throw InputError(fmt::format("CL step {} mm: expected a positive length", options.step));
  }
  if (!(options.angular_step > 0.0) || !std::isfinite(options.angular_step)) {
    throw InputError(
        fmt::format("angular CL step {} rad: expected a positive angle", options.angular_step));
  }
}

int ClSampler::steps(const Move& move, const std::vector<std::string>* sources) const {
  if (move.is_rapid() && !options_.include_rapids) return 0;
  const double length = move.length();
  const double turn = move.axis_angle();
  if (length <= tol::kLength && turn <= tol::kAngle) return 0;  // nothing moves
  const double n = std::max({1.0, std::ceil(length / options_.step - tol::kRelative),
                             std::ceil(turn / options_.angular_step - tol::kRelative)});
  if (!(n <= kMostPerMove)) {  // also NaN: never cast to int
    const std::string file =
        sources != nullptr && static_cast<std::size_t>(move.source) < sources->size()
            ? (*sources)[static_cast<std::size_t>(move.source)]
            : std::string();
    throw InputError(
        SourceLocation{file, move.line},
        fmt::format("this move would get {:.3g} cutter locations ({:.6g} mm at {:g} "
                    "mm, {:.4g} rad at {:.4g} rad), more than {:g} in one move: "
                    "raise the CL step (--cl-step, --cl-angle) or check the move",
                    n, length, options_.step, turn, options_.angular_step, kMostPerMove));
  }
  return static_cast<int>(n);
}

void ClSampler::next(const Move& move, int index, std::vector<ClPoint>& out) {
  out.clear();
  const int steps = this->steps(move);
  if (steps == 0) return;
  const double length = move.length();
  const double turn = move.axis_angle();
  // Parameter speed du/dt: the feed is a tip speed (mm/min); a pure re-orientation is fed in
  // degrees per minute, as LinuxCNC feeds rotary-only moves. Rapids have no known rate.
  double du_dt = 0.0;
  if (!move.is_rapid() && move.feed_rate > 0.0) {
    du_dt = length > tol::kLength ? move.feed_rate / 60.0 / length
                                  : move.feed_rate / 60.0 / radians_to_degrees(turn);
  }
  const Vec3 omega_u = move.axis_rate(0.0);
  for (int k = 0; k < steps; ++k) {
    const double u = static_cast<double>(k) / steps;
    ClPoint p;
    p.position = move.position(u);
    p.axis = move.axis(u);
    const Vec3 tangent = move.tangent(u);
    const double speed = tangent.norm();
    p.feed_direction = speed > tol::kLength ? Vec3(tangent / speed) : Vec3::Zero();
    p.velocity = tangent * du_dt;
    p.angular_velocity = omega_u * du_dt;
    p.move = index;
    p.line = move.line;
    p.u = u;
    p.path_length = path_length_ + u * length;
    out.push_back(p);
  }
  path_length_ += length;
}

std::vector<ClPoint> sample_cl_points(const Toolpath& path, const SamplingOptions& options) {
  ClSampler sampler(options);
  std::vector<ClPoint> points, one;
  for (std::size_t m = 0; m < path.moves.size(); ++m) {
    sampler.next(path.moves[m], static_cast<int>(m), one);
    points.insert(points.end(), one.begin(), one.end());
  }
  return points;
}

std::size_t count_cl_points(const Toolpath& path, const SamplingOptions& options) {
  const ClSampler sampler(options);
  std::size_t count = 0;
  for (const Move& move : path.moves) {
    count += static_cast<std::size_t>(sampler.steps(move, &path.sources));
  }
  return count;
}

}  // namespace cwe
