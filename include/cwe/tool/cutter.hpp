#pragma once
// A milling cutter: a revolved Profile (the cutting part) plus the data a force model and a
// collision check need (flutes, helix angle, shank).
//
// Everything here is in the tool coordinate system (TCS) of docs/architecture.md: origin at the
// tip, z along the axis towards the shank. A surface point is addressed by its patch, its
// engagement angle φ
// and its fraction u along the patch's profile piece; it sits at
//     P(φ, u) = ρ(u)·(sin φ·x + cos φ·y) + z(u)·z
// (φ measured from +y, clockwise seen from the shank; docs/architecture.md, "Conventions").
//
// Each profile piece becomes one patch: a flat bottom (horizontal line at the tip), a horizontal
// step elsewhere, a cylinder, a cone, a sphere (arc centred on the axis) or a torus. The flat top
// disc that closes the solid at z = height is not a patch: it does not cut.

#include <optional>
#include <string>
#include <vector>

#include "cwe/geometry/interval.hpp"
#include "cwe/geometry/ray.hpp"
#include "cwe/geometry/vec.hpp"
#include "cwe/tool/apt.hpp"
#include "cwe/tool/profile.hpp"

namespace cwe {

enum class PatchKind { kFlatBottom, kStep, kCylinder, kCone, kSphere, kTorus };

const char* to_string(PatchKind kind);

// A cylinder about the tool axis bounding a patch or the whole cutter.
struct BoundingCylinder {
  double radius = 0.0;
  double z_min = 0.0;
  double z_max = 0.0;
};

struct CutterPatch {
  PatchKind kind = PatchKind::kCylinder;
  int segment = 0;  // index of its piece in the profile
  BoundingCylinder bounds;
};

// Where a point of the cutter surface sits in the engagement parameter plane.
struct EngagementCoordinates {
  int patch = 0;
  double phi = 0.0;       // engagement angle, radians in [0, 2π)
  double depth = 0.0;     // height above the tip (side patches' map coordinate), mm
  double radius = 0.0;    // distance from the axis (the flat bottom's polar coordinate), mm
  double u = 0.0;         // fraction along the patch's profile piece
  double distance = 0.0;  // distance of the query point from the surface, mm
  bool polar = false;     // true on the flat bottom: the map is (radius, φ), not (φ, depth)
};

struct Shank {
  double diameter = 0.0;  // mm
  double length = 0.0;    // mm, above the cutting part
};

struct CutterOptions {
  std::string name;  // a label for reports (defaults to the specification)
  int flutes = 0;    // 0: default (2 for pointed or ball tips, 4 otherwise)
  double helix_angle_deg = 30.0;
  std::optional<Shank> shank;    // default: diameter of the top edge, length 2 × diameter
  std::optional<AptCutter> apt;  // the APT parameters the profile was built from, if any
};

class Cutter {
 public:
  explicit Cutter(Profile profile, CutterOptions options = {});

  const std::string& name() const { return name_; }
  const Profile& profile() const { return profile_; }
  const std::vector<CutterPatch>& patches() const { return patches_; }
  int flutes() const { return flutes_; }
  double helix_angle() const { return helix_angle_; }  // radians
  const Shank& shank() const { return shank_; }
  const std::optional<AptCutter>& apt() const { return apt_; }

  double diameter() const { return 2.0 * profile_.max_radius(); }
  double flute_length() const { return profile_.height(); }  // the cutting part's height
  BoundingCylinder bounding_cylinder() const;

  // Surface of patch `patch` at engagement angle φ and profile fraction u ∈ [0, 1].
  Vec3 point(int patch, double phi, double u) const;
  Vec3 normal(int patch, double phi, double u) const;  // outward, unit
  // Implicit value of the patch's full surface (sphere, torus, cylinder, cone, plane: Aras 2008
  // eq. 6.7), zero on the patch, negative inside; units mm² (plane: mm; torus: mm⁴).
  double implicit_value(int patch, const Vec3& p) const;

  // The ray's chords through the part of the solid swept by the patch's piece:
  // { z within the piece's height range, ρ ≤ radius of the piece at z }.
  std::vector<Interval> intersect_patch(int patch, const Ray& ray) const;
  // The ray's chords through the whole solid cutting part (top disc included), sorted and
  // disjoint.
  std::vector<Interval> intersect(const Ray& ray) const;
  // Closed membership of a TCS point in the solid cutting part.
  bool contains(const Vec3& p) const;

  // Engagement coordinates of the surface point nearest to p (p in TCS).
  EngagementCoordinates engagement_coordinates(const Vec3& p) const;

 private:
  const ProfileSegment& segment_of(int patch) const;

  Profile profile_;
  std::vector<CutterPatch> patches_;
  std::string name_;
  int flutes_ = 2;
  double helix_angle_ = 0.0;
  Shank shank_;
  std::optional<AptCutter> apt_;
};

}  // namespace cwe
