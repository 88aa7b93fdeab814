#pragma once
// Cutter–workpiece engagement (CWE) at one cutter location, in the cutter's parameter plane
// (docs/architecture.md conventions; docs/engagement.md).
//
// A point P of the cutter surface is engaged when it moves into the material (f = N·V > 0: the
// forward part of the feasible contact surface; grazing points, f = 0, are not engaged) and the
// workpiece, as cut by all motion before the cutter location, has material immediately outside
// the cutter at P.
//
// The map:
//  - side: the non-horizontal part of the profile (cylinder, cone, sphere, torus patches) in
//    axial discs of height `disc_height` from the tip up, each with the engaged intervals of the
//    engagement angle φ (radians, within [0, 2π], sorted and disjoint; an interval never wraps
//    through φ = 0: engagement across it is two intervals, [a, 2π] and [0, b]);
//  - bottom: a flat bottom (horizontal piece at the tip) in rings of width `disc_height` from the
//    axis outwards, each with its engaged φ intervals.
// Horizontal steps higher up a profile (JSON profiles only; no APT cutter has one) are not mapped.

#include <vector>

#include "cwe/geometry/interval.hpp"

namespace cwe {

// One axial disc of the side: heights z0 < z1 above the tip (mm).
struct DiscEngagement {
  double z0 = 0.0;
  double z1 = 0.0;
  int patch = 0;              // the cutter patch at the disc's mid-height
  std::vector<Interval> phi;  // engaged angles, radians
};

// One ring of the flat bottom: radii r0 < r1 from the axis (mm).
struct RingEngagement {
  double r0 = 0.0;
  double r1 = 0.0;
  std::vector<Interval> phi;
};

struct EngagementMap {
  // Every disc and ring of the cutter, engaged or not, bottom to top and inside out (so maps of
  // different cutter locations line up).
  std::vector<DiscEngagement> discs;
  std::vector<RingEngagement> rings;

  // Summaries.
  bool engaged = false;
  // Where engagement starts and ends going round the cutter in the direction of φ: the ends of
  // the largest φ gap that no disc or ring engages (radians in [0, 2π]; entry may exceed exit
  // when the engagement spans φ = 0). A full ring gives entry 0 and exit 2π; no engagement 0, 0.
  double phi_entry = 0.0;
  double phi_exit = 0.0;
  // Height above the tip of the highest engaged side disc's top, mm (0 when only the bottom, or
  // nothing, is engaged).
  double axial_depth = 0.0;
  // Engaged area on the cutter surface, side and bottom, mm².
  double area = 0.0;
};

// The grid of an extractor's maps, and how close removed material must come to count.
struct EngagementOptions {
  double disc_height = 0.0;  // mm; 0: the workpiece's resolution (dexel: the ray spacing s)
  double phi_step = 0.0;     // rad; 0: an arc of s at the cutter's largest radius, ≤ 1°
  double contact = 0.0;      // mm; 0: s/10 (the default sweep tolerance)
  // Dexel: skip a cell whose point lies farther from the step's removal box than any stretch its
  // test can touch (exact: the same maps, with less work). Off only to check that in the tests.
  bool skip_far_cells = true;
  // Dexel: the side discs of an upright tool whose circles lie above or below the step's
  // removal box, beyond the far-cell test's largest margin, are not visited (exact: each would
  // be skipped whole by its first test). Off only to check that in the tests.
  bool skip_far_discs = true;
  // Dexel: a side disc of an upright tool's cylindrical part takes the intervals of the last
  // disc scanned when its front is the same and the X and Y rays its cells read lost in the step
  // what that disc's rays lost (exact: the same maps, with less work). Off only to check that in
  // the tests.
  bool reuse_alike_discs = true;
};

}  // namespace cwe
