#include "cwe/toolpath/cl_sampling.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cwe/geometry/tolerance.hpp"

namespace cwe {

double default_cl_step(double tool_diameter) { return std::min(0.5, tool_diameter / 20.0); }

std::vector<ClPoint> sample_cl_points(const Toolpath& path, const SamplingOptions& options) {
  if (!(options.step > 0.0) || !std::isfinite(options.step)) {
    throw InputError(fmt::format("CL step {} mm: expected a positive length", options.step));
  }
  if (!(options.angular_step > 0.0) || !std::isfinite(options.angular_step)) {
    throw InputError(
        fmt::format("angular CL step {} rad: expected a positive angle", options.angular_step));
  }
  std::vector<ClPoint> points;
  double path_length = 0.0;
  for (std::size_t m = 0; m < path.moves.size(); ++m) {
    const Move& move = path.moves[m];
    if (move.is_rapid() && !options.include_rapids) continue;
    const double length = move.length();
    const double turn = move.axis_angle();
    if (length <= tol::kLength && turn <= tol::kAngle) continue;  // nothing moves
    const auto steps =
        static_cast<int>(std::max({1.0, std::ceil(length / options.step - tol::kRelative),
                                   std::ceil(turn / options.angular_step - tol::kRelative)}));
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
      p.move = static_cast<int>(m);
      p.line = move.line;
      p.u = u;
      p.path_length = path_length + u * length;
      points.push_back(p);
    }
    path_length += length;
  }
  return points;
}

}  // namespace cwe
