#pragma once
// Exact ray chords through the volume a convex cutter sweeps along a linear move with a constant
// axis (3-axis and 3+2 moves): the removal primitive of the tri-dexel workpiece.
//
// The swept volume SV = T ⊕ [0, 1]·D of a convex tool T translated by D is convex, so a line
// meets it in one interval. Its boundary is covered by the tool at the start, the tool at the end
// and the tool's shadow boundary swept along D (Aras 2008 ch. 4): on each smooth patch the
// grazing curve (N·D = 0: sin φ = -n_z D_z / (n_ρ D_x) in the move's TCS), and at each profile
// vertex (a joint, the tip or the top edge, where the normal jumps) the vertex circle. Every point
// of these surfaces is a point of the tool at some instant, so it lies in SV; the chord is
// therefore exactly the hull of the ray's crossings with them:
//  - the tool at both ends: Cutter::intersect;
//  - swept vertex circles: with n = d × D, n·(C(φ) - o) = 0 is a sin φ + b cos φ + c = 0;
//  - swept grazing curves of lines: the generator is straight, so the crossing is linear;
//  - swept grazing curves of arcs (sphere, torus: Aras 2008 eq. 4.54): the crossing function of
//    the arc angle is sampled and each sign change refined by Brent's method.
// Rays along D (n = 0) need only the two tool chords. Crossings are taken only where the sweep
// parameter λ ∈ [0, 1].

#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/interval.hpp"
#include "cwe/geometry/ray.hpp"
#include "cwe/tool/cutter.hpp"

namespace cwe {

class LinearSweep {
 public:
  // The sweep of `cutter` with unit `axis` from tip `start` to tip `end`. The cutter must be
  // convex (every APT cutter is): InputError otherwise.
  // The sweep keeps a reference to the cutter, which must outlive it.
  LinearSweep(const Cutter& cutter, const Vec3& start, const Vec3& end, const Vec3& axis);
  LinearSweep(Cutter&&, const Vec3&, const Vec3&, const Vec3&) = delete;

  // The interval of ray parameters inside the swept volume (empty if the ray misses it).
  Interval chord(const Ray& ray) const;

  // A box containing the swept volume.
  const Aabb& bounds() const { return bounds_; }

 private:
  const Cutter* cutter_;
  Frame tcs_;   // at the start tip: z the axis, x the lateral feed (or a fixed fallback)
  Vec3 delta_;  // D in TCS coordinates
  Aabb bounds_;
};

}  // namespace cwe
