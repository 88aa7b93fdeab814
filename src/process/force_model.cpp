#include "cwe/process/force_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "cwe/core/error.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {

namespace {

// One edge element of a flute, as the integrals over its length ℓ along the profile that the
// force needs: with the chip h = c·(A sin κ − B cos κ) (A = f̂·e_r, B = f̂·z), every force
// component is a sum of such moments times the coefficients, so the element's force is exact for
// any profile however fast κ turns across it (the first disc of a ball end turns κ from 0° to
// 11°), up to the 16-chord quadrature below.
struct Element {
  double lag = 0.0;  // helix lag ψ at the element's height, rad
  // ∫dℓ (chip width db and edge length dS: the helix is left out, see force_model.hpp), ∫sin κ,
  // ∫cos κ, ∫sin²κ, ∫cos²κ, ∫sin κ cos κ, ∫ρ, ∫ρ sin κ, ∫ρ cos κ (all dℓ).
  double l = 0.0, s1 = 0.0, c1 = 0.0, s2 = 0.0, c2 = 0.0, sc = 0.0, r = 0.0, rs = 0.0, rc = 0.0;
  // κ at the element's ends (outward normal n = sin κ·e_r − cos κ·z): the range over which the
  // thickest chip is looked for (κ turns monotonically along a convex profile).
  double sin_kappa[2] = {1.0, 1.0}, cos_kappa[2] = {0.0, 0.0};
  double mean_sin_kappa() const { return l > 0.0 ? s1 / l : 0.0; }

  void add(double length, double rho_mid, double sin_k, double cos_k) {
    l += length;
    s1 += sin_k * length;
    c1 += cos_k * length;
    s2 += sin_k * sin_k * length;
    c2 += cos_k * cos_k * length;
    sc += sin_k * cos_k * length;
    r += rho_mid * length;
    rs += rho_mid * sin_k * length;
    rc += rho_mid * cos_k * length;
  }
};

// The side element of the disc z0 < z1, from 16 chords of the profile between the two heights:
// each chord's direction gives κ (sin κ = dz/dℓ, cos κ = dρ/dℓ), exact on lines and within
// (Δκ)²/24 on arcs.
Element side_element(const Profile& profile, double z0, double z1, double lead) {
  z1 = std::min(z1, profile.height());
  Element e;
  e.lag = lead * 0.5 * (z0 + z1);
  constexpr int kChords = 16;
  double rho_prev = profile.radius_at(z0);
  for (int i = 1; i <= kChords; ++i) {
    const double dz = (z1 - z0) / kChords;
    const double rho = profile.radius_at(z0 + dz * i);
    const double length = std::hypot(rho - rho_prev, dz);
    if (length > 0.0) {
      const double sin_k = dz / length, cos_k = (rho - rho_prev) / length;
      e.add(length, 0.5 * (rho + rho_prev), sin_k, cos_k);
    }
    rho_prev = rho;
  }
  // κ at the two ends, from the profile's normal there.
  for (int end = 0; end < 2; ++end) {
    const double z = end == 0 ? z0 : z1;
    const Profile::Location at = profile.closest(Vec2(profile.radius_at(z), z));
    const Vec2 n = profile.segments()[static_cast<std::size_t>(at.segment)].normal_at(at.u);
    e.sin_kappa[end] = n.x();
    e.cos_kappa[end] = -n.y();
  }
  return e;
}

// The flat-bottom ring r0 < r1: a radial edge, normal −z (κ = 0), no helix lag.
Element ring_element(double r0, double r1) {
  Element e;
  e.add(r1 - r0, 0.5 * (r0 + r1), 0.0, 1.0);
  e.sin_kappa[0] = e.sin_kappa[1] = 0.0;
  e.cos_kappa[0] = e.cos_kappa[1] = 1.0;
  return e;
}

// Accumulates the force over one revolution, sample by sample.
class Revolution {
 public:
  Revolution(const CuttingCoefficients& k, const Vec3& feed, double feed_per_tooth, int flutes,
             const Runout& runout, const std::vector<double>& sin_table,
             const std::vector<double>& cos_table)
      : k_(k),
        feed_(feed),
        c_(feed_per_tooth),
        flutes_(flutes),
        runout_(runout),
        sin_(sin_table),
        cos_(cos_table),
        n_(static_cast<int>(sin_table.size())),
        step_(2.0 * kPi / n_),
        f_(static_cast<std::size_t>(n_), Vec3::Zero()),
        torque_(static_cast<std::size_t>(n_), 0.0) {}

  void add(const Element& e, const std::vector<Interval>& phi) {
    for (int j = 0; j < flutes_; ++j) {
      const double pitch = 2.0 * kPi * j / flutes_;
      const double offset = pitch - e.lag;  // φ_j = θ + offset
      const double so = std::sin(offset), co = std::cos(offset);
      for (const Interval& in : phi) {
        if (in.is_empty()) continue;
        thickest_chip(e, j, in);
        if (in.hi - in.lo >= 2.0 * kPi * (1.0 - tol::kRelative)) {  // a full ring: every step, whole
          for (int k = 0; k < n_; ++k) {
            accumulate(e, j, sin_[k] * co + cos_[k] * so, cos_[k] * co - sin_[k] * so, 1.0, k);
          }
          continue;
        }
        // The interval in spindle angle θ, started within [−Δ/2, 2π − Δ/2).
        double a = std::fmod(in.lo - offset + 0.5 * step_, 2.0 * kPi);
        if (a < 0.0) a += 2.0 * kPi;
        a -= 0.5 * step_;
        const double b = a + (in.hi - in.lo);
        const long k0 = std::lround(std::floor((a + 0.5 * step_) / step_));
        const long k1 = std::lround(std::floor((b + 0.5 * step_) / step_));
        for (long k = k0; k <= k1; ++k) {
          const double lo = std::max(a, (static_cast<double>(k) - 0.5) * step_);
          const double hi = std::min(b, (static_cast<double>(k) + 0.5) * step_);
          if (!(hi > lo)) continue;
          // k < 2n + 1 (a ≥ −Δ/2, b < 4π): the index without an integer division.
          int index = static_cast<int>(k);
          while (index >= n_) index -= n_;
          double s, c;
          if (hi - lo >= step_ * (1.0 - tol::kRelative)) {  // the whole step: θ = kΔ from the table
            s = sin_[index] * co + cos_[index] * so;
            c = cos_[index] * co - sin_[index] * so;
          } else {
            const double phi_mid = 0.5 * (lo + hi) + offset;
            s = std::sin(phi_mid);
            c = std::cos(phi_mid);
          }
          accumulate(e, j, s, c, (hi - lo) / step_, index);
        }
      }
    }
  }

  const std::vector<Vec3>& force() const { return f_; }
  const std::vector<double>& torque() const { return torque_; }  // N·mm
  double max_chip() const { return max_chip_; }
  bool cutting() const { return cutting_; }

 private:
  // The largest f̂·n = (f_x sin φ + f_y cos φ) sin κ − f_z cos κ for φ in the interval: at an end
  // or where the sinusoid peaks.
  // The largest A(φ) = f_x sin φ + f_y cos φ for φ in the interval: at an end or where the
  // sinusoid peaks.
  double max_lateral_feed(const Interval& in) const {
    const double alpha = feed_.x(), beta = feed_.y();
    auto a = [&](double p) { return alpha * std::sin(p) + beta * std::cos(p); };
    double best = std::max(a(in.lo), a(in.hi));
    if (alpha != 0.0 || beta != 0.0) {
      double peak = std::atan2(alpha, beta);  // where sin(φ + atan2(β, α)) = 1
      peak += 2.0 * kPi * std::ceil((in.lo - peak) / (2.0 * kPi));
      if (peak <= in.hi) best = std::max(best, a(peak));
    }
    return best;
  }

  // The thickest chip flute j cuts on the element over the interval. f̂·n = A(φ) sin κ − f_z cos κ
  // with sin κ ≥ 0, so φ takes A's largest value A* whatever κ; over the element's κ range the
  // sinusoid A* sin κ − f_z cos κ peaks at an end or at κ* = atan2(A*, −f_z), where it is
  // √(A*² + f_z²).
  void thickest_chip(const Element& e, int j, const Interval& in) {
    const double a = max_lateral_feed(in), fz = feed_.z();
    for (int end = 0; end < 2; ++end) {
      const double g = a * e.sin_kappa[end] - fz * e.cos_kappa[end];
      max_chip_ = std::max(max_chip_, chip(j, g, e.sin_kappa[end], e.lag));
    }
    const double k0 = std::atan2(e.sin_kappa[0], e.cos_kappa[0]);
    const double k1 = std::atan2(e.sin_kappa[1], e.cos_kappa[1]);
    const double peak = std::atan2(a, -fz);
    if (peak > std::min(k0, k1) && peak < std::max(k0, k1)) {
      max_chip_ = std::max(max_chip_, chip(j, std::hypot(a, fz), std::sin(peak), e.lag));
    }
  }

  // Chip thickness of flute j where the feed along the normal is g: c·g, or with runout the
  // thinnest of the chips left by the m-th tooth before it, m·c·g + (r_j − r_{j−m})·sin κ.
  // The flute's radial offset follows it round the helix: at lag ψ it is e·cos(λ − 2πj/N + ψ).
  double chip(int j, double g, double sin_kappa, double lag) const {
    const double h1 = c_ * g;
    if (runout_.offset <= 0.0) return h1;
    const double rj = runout_.offset * std::cos(runout_.angle - 2.0 * kPi * j / flutes_ + lag);
    double h = std::numeric_limits<double>::infinity();
    for (int m = 1; m <= flutes_; ++m) {
      const double rm =
          runout_.offset * std::cos(runout_.angle - 2.0 * kPi * (j - m) / flutes_ + lag);
      h = std::min(h, m * h1 + (rj - rm) * sin_kappa);
    }
    return h;
  }

  void accumulate(const Element& e, int j, double s, double c, double weight, int index) {
    // The chip h = c·(A sin κ − B cos κ) integrated over the element: c·(A·∫sin κ − B·∫cos κ).
    const double a = feed_.x() * s + feed_.y() * c, b = feed_.z();
    const double area_per_feed = a * e.s1 - b * e.c1;  // ∫g dℓ
    if (!(area_per_feed > 0.0)) return;
    // With runout the flute's chip is not c·g: scale the feed by the ratio at the mean g (a
    // division only then: it is most of this function's time when paid for every sample).
    double feed = c_;
    if (runout_.offset > 0.0) {
      const double g = area_per_feed / e.l;
      feed = chip(j, g, e.mean_sin_kappa(), e.lag) / g;
    }
    if (!(feed > 0.0)) return;
    cutting_ = true;
    // ∫dF_t, ∫dF_r sin κ, ∫dF_r cos κ, ∫dF_a sin κ, ∫dF_a cos κ, ∫ρ dF_t.
    const double ft = k_.ktc * feed * area_per_feed + k_.kte * e.l;
    const double fr_s = k_.krc * feed * (a * e.s2 - b * e.sc) + k_.kre * e.s1;
    const double fr_c = k_.krc * feed * (a * e.sc - b * e.c2) + k_.kre * e.c1;
    const double fa_s = k_.kac * feed * (a * e.s2 - b * e.sc) + k_.kae * e.s1;
    const double fa_c = k_.kac * feed * (a * e.sc - b * e.c2) + k_.kae * e.c1;
    const double torque = k_.ktc * feed * (a * e.rs - b * e.rc) + k_.kte * e.r;
    const double q = fr_s + fa_c;
    f_[static_cast<std::size_t>(index)] +=
        weight * Vec3(-ft * c - q * s, ft * s - q * c, fr_c - fa_s);
    torque_[static_cast<std::size_t>(index)] += weight * torque;
  }

  const CuttingCoefficients& k_;
  Vec3 feed_;
  double c_;
  int flutes_;
  Runout runout_;
  const std::vector<double>& sin_;
  const std::vector<double>& cos_;
  int n_;
  double step_;
  std::vector<Vec3> f_;
  std::vector<double> torque_;
  double max_chip_ = 0.0;
  bool cutting_ = false;
};

}  // namespace

double feed_per_tooth(double feed_rate, int flutes, double spindle_speed) {
  if (!(spindle_speed > 0.0) || flutes < 1 || !(feed_rate > 0.0)) return 0.0;
  return feed_rate / (flutes * spindle_speed);
}

ForceModel::ForceModel(const Cutter& cutter, CuttingCoefficients coefficients,
                       ForceModelOptions options)
    : profile_(cutter.profile()), coefficients_(std::move(coefficients)), runout_(options.runout) {
  if (!(options.angle_step >= kMinAngleStep) || options.angle_step > kPi / 2.0 * (1.0 + tol::kRelative)) {
    throw InputError(fmt::format("the spindle angle step must be in [0.01°, 90°], not {:g}°",
                                 options.angle_step * 180.0 / kPi));
  }
  flutes_ = options.flutes > 0 ? options.flutes : cutter.flutes();
  if (options.flutes < 0 || flutes_ < 1) {
    throw InputError(fmt::format("a cutter needs at least one flute, not {}", options.flutes));
  }
  helix_ = options.helix_angle >= 0.0 ? options.helix_angle : cutter.helix_angle();
  if (!(helix_ >= 0.0) || helix_ >= kPi / 2.0) {
    throw InputError(
        fmt::format("the helix angle must be in [0°, 90°), not {:g}°", helix_ * 180.0 / kPi));
  }
  if (!(runout_.offset >= 0.0) || !std::isfinite(runout_.offset) || !std::isfinite(runout_.angle)) {
    throw InputError(
        fmt::format("the runout offset must be a finite length >= 0 mm, not {:g}", runout_.offset));
  }
  const double radius = cutter.profile().max_radius();
  lead_ = radius > 0.0 ? std::tan(helix_) / radius : 0.0;
  samples_ = std::max(4, static_cast<int>(std::lround(2.0 * kPi / options.angle_step)));
  step_ = 2.0 * kPi / samples_;
  sin_.resize(static_cast<std::size_t>(samples_));
  cos_.resize(static_cast<std::size_t>(samples_));
  for (int k = 0; k < samples_; ++k) {
    sin_[static_cast<std::size_t>(k)] = std::sin(k * step_);
    cos_[static_cast<std::size_t>(k)] = std::cos(k * step_);
  }
}

ClForces ForceModel::evaluate(const EngagementMap& map, const ToolState& state,
                              double feed_per_tooth, double spindle_speed, bool keep_curve) const {
  const Vec3 v = state.tip_velocity_tcs();
  const double speed = v.norm();
  const Vec3 feed = speed > 0.0 ? Vec3(v / speed) : Vec3::Zero();
  return evaluate(map, feed, feed_per_tooth, spindle_speed, keep_curve, &state.tcs);
}

ClForces ForceModel::evaluate(const EngagementMap& map, const Vec3& feed_direction_tcs,
                              double feed_per_tooth, double spindle_speed, bool keep_curve) const {
  return evaluate(map, feed_direction_tcs, feed_per_tooth, spindle_speed, keep_curve, nullptr);
}

ClForces ForceModel::evaluate(const EngagementMap& map, const Vec3& feed_direction_tcs,
                              double feed_per_tooth, double spindle_speed, bool keep_curve,
                              const Frame* world) const {
  ClForces out;
  out.feed_per_tooth = feed_per_tooth;
  out.spindle_speed = spindle_speed;
  Revolution revolution(coefficients_, feed_direction_tcs, feed_per_tooth, flutes_, runout_, sin_,
                        cos_);
  if (map.engaged && feed_per_tooth > 0.0 && feed_direction_tcs.squaredNorm() > 0.0) {
    const Profile& profile = profile_;
    for (const DiscEngagement& disc : map.discs) {
      if (disc.phi.empty() || disc.z0 >= profile.height()) continue;
      revolution.add(side_element(profile, disc.z0, disc.z1, lead_), disc.phi);
    }
    for (const RingEngagement& ring : map.rings) {
      if (ring.phi.empty()) continue;
      revolution.add(ring_element(ring.r0, ring.r1), ring.phi);
    }
  }
  out.cutting = revolution.cutting();
  out.max_chip = revolution.max_chip();
  const double omega = spindle_speed * 2.0 * kPi / 60.0;  // rad/s
  Vec3 sum = Vec3::Zero();
  double torque_sum = 0.0;
  for (int k = 0; k < samples_; ++k) {
    const Vec3& f = revolution.force()[static_cast<std::size_t>(k)];
    const double t = revolution.torque()[static_cast<std::size_t>(k)] / 1000.0;  // N·m
    sum += f;
    torque_sum += t;
    out.peak_force = out.peak_force.cwiseMax(f.cwiseAbs());
    if (world != nullptr) {
      out.peak_force_world = out.peak_force_world.cwiseMax(world->direction_to_world(f).cwiseAbs());
    }
    out.peak_resultant = std::max(out.peak_resultant, f.norm());
    out.peak_torque = std::max(out.peak_torque, std::abs(t));
    if (keep_curve) out.curve.push_back({k * step_, f, t});
  }
  out.mean_force = sum / samples_;
  out.mean_force_world =
      world != nullptr ? Vec3(world->direction_to_world(out.mean_force)) : out.mean_force;
  if (world == nullptr) out.peak_force_world = out.peak_force;
  out.mean_torque = torque_sum / samples_;
  out.mean_power = out.mean_torque * omega;
  return out;
}

}  // namespace cwe
