// Engagement maps against a brute-force oracle: dense points of the cutter surface tested against
// the exact workpiece (the block minus the true swept volume of all motion before the cutter
// location) and the true swept volume of the step that follows it, both decided by
// test::union_side over densely sampled tool positions, for a bull-nose ramp beside an earlier
// slot and a tilted 3+2 pass. A point is engaged where the step removes material next to it
// (CWE = FCS ∩ (W ∩ SV)).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cwe/engagement/dexel_engagement.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "envelope/sweep_oracle.hpp"

namespace cwe {
namespace {

constexpr double kSpacing = 0.1;

Move line(const Vec3& a, const Vec3& b, const Vec3& axis = Vec3::UnitZ()) {
  Move m;
  m.start = a;
  m.end = b;
  m.start_axis = m.end_axis = axis.normalized();
  m.feed_rate = 600.0;
  return m;
}

struct Case {
  const char* tool;
  Aabb block;
  std::vector<Move> moves;
  double along_last = 0.6;  // the CL to check: this fraction along the last move
};

// The map's verdict at a surface point given by (φ, height z) on the side or (φ, radius) on the
// bottom.
bool map_engaged(const std::vector<Interval>& phi, double angle) {
  for (const Interval& i : phi) {
    if (angle >= i.lo && angle <= i.hi) return true;
  }
  return false;
}

void check(const Case& c) {
  TriDexel stock = TriDexel::from_box(c.block, kSpacing);
  const Move& last = c.moves.back();
  const Vec3 probe = last.position(c.along_last);
  Toolpath path;
  path.sources = {"test"};
  path.moves = c.moves;
  const Cutter cutter = cutter_from_spec(c.tool);
  SimulationOptions options;
  options.resolution = kSpacing;
  SamplingOptions sampling;
  sampling.step = 0.5;
  EngagementMap map;
  ClPoint cl;
  ToolState state;
  double nearest = 1e300;
  std::vector<ClPoint> cls;
  std::size_t chosen = 0;
  simulate_engagement(
      stock, cutter, path, options, sampling, {},
      [&](std::size_t k, const ClPoint& p, const ToolState& s, const EngagementMap& m) {
        cls.push_back(p);
        const double d = (p.position - probe).norm();
        if (d < nearest) {
          nearest = d;
          map = m;
          cl = p;
          state = s;
          chosen = k;
        }
      });
  ASSERT_LT(nearest, 0.5);
  ASSERT_TRUE(map.engaged);
  // The step that follows the CL: to the next sample of the same move, or to the move's end.
  const double u_next =
      chosen + 1 < cls.size() && cls[chosen + 1].move == cl.move ? cls[chosen + 1].u : 1.0;
  const Move step = c.moves[static_cast<std::size_t>(cl.move)].part(cl.u, u_next);

  // The motion before the CL: the earlier moves whole and the current one up to u.
  std::vector<Move> before(c.moves.begin(), c.moves.begin() + cl.move);
  if (cl.u > 0.0) before.push_back(c.moves[static_cast<std::size_t>(cl.move)].part(0.0, cl.u));
  const BoundingCylinder b = cutter.bounding_cylinder();
  const double reach = std::hypot(b.radius, b.z_max);
  // Material δ outside P that the step removes: δ within the map's contact tolerance (s/10), and
  // the step's sweep reaches past it wherever f ≥ 0.1|V| (at 6° from grazing a 4 mm radius
  // sweeps 0.022 mm beyond its surface). The band covers the swept volumes' rounding only.
  const double delta = kSpacing / 20, band = 1e-4;
  const auto material = [&](const Vec3& p) {  // +1 material, -1 none, 0 undecided
    if (!c.block.contains(p)) return -1;
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
  int agreed = 0, engaged = 0;
  const int kPhi = 120;
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
    for (int k = 0; k < kPhi; ++k) {
      const double phi = (k + 0.5) * 2 * kPi / kPhi;
      const double dphi = 1.5 * kSpacing / std::max(rho, kSpacing);
      const int verdict = at(phi, z);
      if (verdict == 0) continue;
      if (at(phi - dphi, z) != verdict || at(phi + dphi, z) != verdict ||
          at(phi, std::max(0.0, z - 1.5 * kSpacing)) != verdict ||
          at(phi, z + 1.5 * kSpacing) != verdict) {
        continue;
      }
      ASSERT_EQ(map_engaged(disc.phi, phi), verdict > 0)
          << c.tool << ": disc " << disc.z0 << "–" << disc.z1 << " φ " << phi * 180 / kPi;
      ++agreed;
      engaged += verdict > 0 ? 1 : 0;
    }
  }
  // Bottom rings.
  for (const RingEngagement& ring : map.rings) {
    const double r = 0.5 * (ring.r0 + ring.r1);
    const auto at = [&](double phi, double radius) {
      const Vec3 radial = std::sin(phi) * tcs.x() + std::cos(phi) * tcs.y();
      return oracle(tcs.origin + radius * radial, -tcs.z());
    };
    for (int k = 0; k < kPhi; ++k) {
      const double phi = (k + 0.5) * 2 * kPi / kPhi;
      const int verdict = at(phi, r);
      if (verdict == 0) continue;
      const double dphi = 1.5 * kSpacing / std::max(r, kSpacing);
      if (at(phi - dphi, r) != verdict || at(phi + dphi, r) != verdict ||
          at(phi, std::max(0.0, r - 1.5 * kSpacing)) != verdict ||
          at(phi, r + 1.5 * kSpacing) != verdict) {
        continue;
      }
      ASSERT_EQ(map_engaged(ring.phi, phi), verdict > 0)
          << c.tool << ": ring " << ring.r0 << "–" << ring.r1 << " φ " << phi * 180 / kPi;
      ++agreed;
      engaged += verdict > 0 ? 1 : 0;
    }
  }
  EXPECT_GT(agreed, 500);
  EXPECT_GT(engaged, 100);
  EXPECT_GT(agreed - engaged, 100);
}

TEST(EngagementOracle, BullNoseRampBesideASlot) {
  // A slot along X at depth 2, then a bull-nose ramp crossing it diagonally, descending.
  check({"bull:10,2,6",
         {{0, 0, 4}, {36, 30, 12}},
         {line({-8, 12, 10}, {48, 12, 10}), line({-8, 4, 11}, {30, 22, 7})}});
}

TEST(EngagementOracle, TiltedThreePlusTwo) {
  // A flat end mill with its axis tilted about 20° from Z, side-cutting along X, then a ramp
  // along the first cut's wall.
  const Vec3 axis(std::sin(20 * kPi / 180), -std::sin(10 * kPi / 180), 1.0);
  check({"flat:8,6",
         {{0, 0, 4}, {36, 30, 12}},
         {line({-8, 25, 8}, {48, 25, 8}, axis), line({-8, 15, 9}, {40, 21, 7.5}, axis)}});
}

}  // namespace
}  // namespace cwe
