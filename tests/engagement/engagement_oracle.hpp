#pragma once
// A brute-force oracle for engagement maps: dense points of the cutter surface tested against the
// exact workpiece (the block minus the true swept volume of all motion before the cutter
// location) and the true swept volume of the step that follows it, both decided by
// test::union_side over densely sampled tool positions. A point is engaged where the step removes
// material next to it (CWE = FCS ∩ (W ∩ SV)). Points within about 6° of grazing, or whose
// neighbours 1.5 s away on the surface disagree (the map places boundaries within s/√2), are not
// judged.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cwe/engagement/engagement_map.hpp"
#include "cwe/kinematics/tool_state.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "envelope/sweep_oracle.hpp"

namespace cwe::test {

// The map's verdict at a surface point given by (φ, height z) on the side or (φ, radius) on the
// bottom.
inline bool map_engaged(const std::vector<Interval>& phi, double angle) {
  for (const Interval& i : phi) {
    if (angle >= i.lo && angle <= i.hi) return true;
  }
  return false;
}

struct OracleCount {
  int agreed = 0;   // points judged, all in agreement (a disagreement fails the test)
  int engaged = 0;  // of those, engaged
};

// Checks `map`, found at `cl` (tool `state`) of `moves` cut through the box `block` at ray spacing
// `spacing`, where the step after the CL ends at parameter `u_next` of the same move.
inline OracleCount check_against_oracle(const Cutter& cutter, const Aabb& block,
                                        const std::vector<Move>& moves, const ClPoint& cl,
                                        const ToolState& state, const EngagementMap& map,
                                        double u_next, double spacing) {
  const double kSpacing = spacing;
  const Move step = moves[static_cast<std::size_t>(cl.move)].part(cl.u, u_next);
  // The motion before the CL: the earlier moves whole and the current one up to u.
  std::vector<Move> before(moves.begin(), moves.begin() + cl.move);
  if (cl.u > 0.0) before.push_back(moves[static_cast<std::size_t>(cl.move)].part(0.0, cl.u));
  const BoundingCylinder b = cutter.bounding_cylinder();
  const double reach = std::hypot(b.radius, b.z_max);
  // Material δ outside P that the step removes: δ within the map's contact tolerance (s/10), and
  // the step's sweep reaches past it wherever f ≥ 0.1|V| (at 6° from grazing a 4 mm radius
  // sweeps 0.022 mm beyond its surface). The band covers the swept volumes' rounding only.
  const double delta = kSpacing / 20, band = 1e-4;
  const auto material = [&](const Vec3& p) {  // +1 material, -1 none, 0 undecided
    if (!block.contains(p)) return -1;
    int verdict = 1;
    for (const Move& m : before) {
      const int side = test::union_side(cutter, m, p, band, reach);
      if (side < 0) return -1;
      verdict = std::min(verdict, side);
    }
    return verdict;
  };
  const Frame& tcs = state.tcs;
  const double speed = state.tip_velocity.norm();
  // Oracle engagement at a surface point with outward normal (world): +1, -1 or 0 (grazing or
  // undecided).
  const auto oracle = [&](const Vec3& p, const Vec3& n) {
    const double f = n.dot(state.point_velocity(p));
    if (std::abs(f) < 0.1 * speed) return 0;  // within ~6° of grazing
    if (f < 0.0) return -1;
    const Vec3 q = p + delta * n;
    const int side = test::union_side(cutter, step, q, band, reach);  // -1 inside the sweep
    if (side > 0) return -1;  // the step does not reach q: nothing is removed there
    return side < 0 ? material(q) : 0;
  };

  const Profile& profile = cutter.profile();
  OracleCount count;
  int& agreed = count.agreed;
  int& engaged = count.engaged;
  const int kPhi = 120;
  // Judges the map's intervals `phi_map` round one disc or ring (`label`): at(φ, w) gives the
  // oracle's verdict, w the disc's height or the ring's radius, rho its radius. A point is judged only where its neighbours 1.5 s
  // away on the surface (in φ and in w) agree with it.
  const auto judge = [&](const auto& at, double w, double rho, const std::vector<Interval>& phi_map,
                         const std::string& label) {
    const double dphi = 1.5 * kSpacing / std::max(rho, kSpacing);
    for (int k = 0; k < kPhi; ++k) {
      const double phi = (k + 0.5) * 2 * kPi / kPhi;
      const int verdict = at(phi, w);
      if (verdict == 0) continue;
      if (at(phi - dphi, w) != verdict || at(phi + dphi, w) != verdict ||
          at(phi, std::max(0.0, w - 1.5 * kSpacing)) != verdict ||
          at(phi, w + 1.5 * kSpacing) != verdict) {
        continue;
      }
      EXPECT_EQ(map_engaged(phi_map, phi), verdict > 0)
          << cutter.name() << ": " << label << " φ " << phi * 180 / kPi;
      ++agreed;
      engaged += verdict > 0 ? 1 : 0;
    }
  };
  // Side: heights up to the block's reach, each checked with its neighbours 1.5 s away on the
  // surface (the map places boundaries within s/√2; the disc spans s).
  for (const DiscEngagement& disc : map.discs) {
    const double z = 0.5 * (disc.z0 + disc.z1);
    if (z < 2 * kSpacing || z > profile.height() - 2 * kSpacing) continue;
    const double rho = profile.radius_at(z);
    const Vec2 normal = profile
                            .segments()[static_cast<std::size_t>(
                                cutter.patches()[static_cast<std::size_t>(disc.patch)].segment)]
                            .normal_at(profile.closest(Vec2(rho, z)).u);
    const auto at = [&](double phi, double height) {
      const double r = profile.radius_at(height);
      const Vec3 radial = std::sin(phi) * tcs.x() + std::cos(phi) * tcs.y();
      return oracle(tcs.origin + r * radial + height * tcs.z(),
                    (normal.x() * radial + normal.y() * tcs.z()).normalized());
    };
    judge(at, z, rho, disc.phi, fmt::format("disc {}–{}", disc.z0, disc.z1));
  }
  // Bottom rings.
  for (const RingEngagement& ring : map.rings) {
    const double r = 0.5 * (ring.r0 + ring.r1);
    const auto at = [&](double phi, double radius) {
      const Vec3 radial = std::sin(phi) * tcs.x() + std::cos(phi) * tcs.y();
      return oracle(tcs.origin + radius * radial, -tcs.z());
    };
    judge(at, r, r, ring.phi, fmt::format("ring {}–{}", ring.r0, ring.r1));
  }
  return count;
}

}  // namespace cwe::test
