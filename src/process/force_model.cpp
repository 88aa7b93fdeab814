#include "cwe/process/force_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
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

// Accumulates the force over one revolution. The steps an element spends wholly inside an
// engaged interval are summed in closed form: without runout an element's force is a sum of
// harmonics of order 0, 1 and 2 in φ (the chip is linear in sin φ and cos φ, and the force is
// the chip times sin φ or cos φ), so each run of whole steps adds its 5 harmonic coefficients
// per component to a difference array over the steps, and one pass at the end sums them and
// evaluates the revolution: O(samples + elements) instead of O(samples × elements). The steps
// at an interval's ends, which an element spends only partly inside, and every step under
// runout (whose chip is not linear in the feed) are evaluated one by one.
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
    for (const Interval& in : phi) {
      if (!in.is_empty()) thickest_chip(e, in);
    }
    const Arc arc = chip_arc(e);
    for (int j = 0; j < flutes_; ++j) {
      const double pitch = 2.0 * kPi * j / flutes_;
      const double offset = pitch - e.lag;  // φ_j = θ + offset
      const Rotation at{offset, std::sin(offset), std::cos(offset)};
      for (const Interval& in : phi) {
        if (in.is_empty()) continue;
        // A full ring: every step, whole.
        if (in.hi - in.lo >= 2.0 * kPi * (1.0 - tol::kRelative)) {
          whole_steps(e, j, at, arc, 0, n_ - 1);
          continue;
        }
        // The interval in spindle angle θ, started within [−Δ/2, 2π − Δ/2).
        double a = std::fmod(in.lo - offset + 0.5 * step_, 2.0 * kPi);
        if (a < 0.0) a += 2.0 * kPi;
        a -= 0.5 * step_;
        const double b = a + (in.hi - in.lo);
        const long k0 = std::lround(std::floor((a + 0.5 * step_) / step_));
        const long k1 = std::lround(std::floor((b + 0.5 * step_) / step_));
        // Every step between k0 and k1 is whole; k0 and k1 may be whole too, or partly inside
        // (evaluated at the middle of their part), or not reached.
        const auto whole_end = [&](long k) {
          const double lo = std::max(a, (static_cast<double>(k) - 0.5) * step_);
          const double hi = std::min(b, (static_cast<double>(k) + 0.5) * step_);
          if (!(hi > lo)) return false;
          if (hi - lo >= step_ * (1.0 - tol::kRelative)) return true;
          const double phi_mid = 0.5 * (lo + hi) + offset;
          accumulate(e, j, std::sin(phi_mid), std::cos(phi_mid), (hi - lo) / step_, wrap(k));
          return false;
        };
        const bool first_whole = whole_end(k0);
        const bool last_whole = k1 == k0 ? first_whole : whole_end(k1);
        const long whole0 = first_whole ? k0 : k0 + 1, whole1 = last_whole ? k1 : k1 - 1;
        if (whole0 <= whole1) whole_steps(e, j, at, arc, whole0, whole1);
      }
    }
  }

  // Adds the closed-form sums of the whole steps to the revolution; call once, after every add.
  void finish() {
    if (changes_.empty()) return;  // no whole step cut
    // The changes by step; a step's in the order they were made.
    std::stable_sort(changes_.begin(), changes_.end(),
                     [](const Change& a, const Change& b) { return a.step < b.step; });
    auto next = changes_.begin();
    Harmonics sum{};
    int active = 0;
    for (int k = 0; k < n_; ++k) {
      if (next != changes_.end() && next->step == k) {
        Harmonics delta{};  // the step's changes summed first, then added
        for (; next != changes_.end() && next->step == k; ++next) {
          // A run's end takes its harmonics away: the same sums as adding their negatives.
          const Harmonics& run = runs_[next->run];
          if (next->runs > 0) {
            for (int m = 0; m < kCoefficients; ++m) delta[m] += run[m];
          } else {
            for (int m = 0; m < kCoefficients; ++m) delta[m] -= run[m];
          }
          active += next->runs;
        }
        for (int m = 0; m < kCoefficients; ++m) sum[m] += delta[m];
      }
      if (active == 0) {  // nothing cuts here: exactly zero, not the rounding of the sums
        sum = Harmonics{};
        continue;
      }
      const int twice = 2 * k >= n_ ? 2 * k - n_ : 2 * k;
      const double basis[5] = {
          1.0, cos_[static_cast<std::size_t>(k)], sin_[static_cast<std::size_t>(k)],
          cos_[static_cast<std::size_t>(twice)], sin_[static_cast<std::size_t>(twice)]};
      double out[4] = {0.0, 0.0, 0.0, 0.0};
      for (int component = 0; component < 4; ++component) {
        for (int h = 0; h < 5; ++h) out[component] += sum[5 * component + h] * basis[h];
      }
      f_[static_cast<std::size_t>(k)] += Vec3(out[0], out[1], out[2]);
      torque_[static_cast<std::size_t>(k)] += out[3];
    }
  }

  const std::vector<Vec3>& force() const { return f_; }
  const std::vector<double>& torque() const { return torque_; }  // N·mm
  double max_chip() const { return max_chip_; }
  bool cutting() const { return cutting_; }

 private:
  // The harmonic coefficients of F_x, F_y, F_z and the torque, each on 1, cos θ, sin θ, cos 2θ,
  // sin 2θ.
  static constexpr int kCoefficients = 20;
  using Harmonics = std::array<double, kCoefficients>;
  // A run of whole steps starts (runs = 1: its harmonics are added) or ends at the step before
  // (runs = −1: they are taken away) at `step`; `run` indexes the harmonics in runs_. Small, so
  // that sorting them by step moves 12 bytes each rather than the harmonics' 160.
  struct Change {
    int step = 0;
    int runs = 0;
    std::uint32_t run = 0;
  };
  struct Rotation {
    double offset, sin, cos;  // φ = θ + offset
  };

  // Step index of k ∈ [0, 2n + 1) (a ≥ −Δ/2, b < 4π), without an integer division.
  int wrap(long k) const {
    int index = static_cast<int>(k);
    while (index >= n_) index -= n_;
    return index;
  }

  // sin φ and cos φ at step k, exactly as the table gives them to `accumulate`.
  void at_step(const Rotation& at, long k, double& s, double& c) const {
    const auto index = static_cast<std::size_t>(wrap(k));
    s = sin_[index] * at.cos + cos_[index] * at.sin;
    c = cos_[index] * at.cos - sin_[index] * at.sin;
  }

  // Whether the element cuts a chip at step k: the test of `accumulate` (the feed per tooth is
  // positive, so without runout only the chip's sign decides).
  bool chip_at(const Element& e, const Rotation& at, long k) const {
    double s, c;
    at_step(at, k, s, c);
    const double a = feed_.x() * s + feed_.y() * c;
    return a * e.s1 - feed_.z() * e.c1 > 0.0;
  }

  // Where an element cuts a chip without runout: A sin φ + B cos φ > T, with A = f_x·∫sin κ,
  // B = f_y·∫sin κ and T = f_z·∫cos κ, is an arc of half-width δ about φ_p (in φ, the same for
  // every flute). r = √(A² + B²); where r is 0 the chip is the same at every step.
  struct Arc {
    double r = 0.0, peak = 0.0, half = 0.0;
  };
  Arc chip_arc(const Element& e) const {
    Arc arc;
    if (runout_.offset > 0.0) return arc;  // not used: the steps are evaluated one by one
    const double big_a = feed_.x() * e.s1, big_b = feed_.y() * e.s1, big_t = feed_.z() * e.c1;
    arc.r = std::hypot(big_a, big_b);
    if (!(arc.r > 0.0)) return arc;
    arc.peak = std::atan2(big_a, big_b);
    arc.half = std::acos(std::clamp(big_t / arc.r, -1.0, 1.0));
    return arc;
  }

  // The whole steps first..last (unwrapped, fewer than n + 1) of flute j on element e, whose
  // chip arc is `arc`.
  void whole_steps(const Element& e, int j, const Rotation& at, const Arc& arc, long first,
                   long last) {
    if (runout_.offset > 0.0) {
      for (long k = first; k <= last; ++k) {
        double s, c;
        at_step(at, k, s, c);
        accumulate(e, j, s, c, 1.0, wrap(k));
      }
      return;
    }
    if (!(arc.r > 0.0)) {  // the same chip at every step
      if (chip_at(e, at, first)) add_run(e, at, first, last);
      return;
    }
    const double peak = arc.peak, half = arc.half;
    // Unwrapped step of angle φ: θ = φ − offset = kΔ.
    const auto step_of = [&](double phi) { return (phi - at.offset) / step_; };
    // Arcs about φ_p + 2πm that can meet the steps' span.
    const double span_lo = static_cast<double>(first) * step_ + at.offset;
    const double span_hi = static_cast<double>(last) * step_ + at.offset;
    const long m0 = std::lround(std::floor((span_lo - peak - half) / (2.0 * kPi)));
    long done = first - 1;  // the last step already given to a run
    for (long m = m0; m <= m0 + 3; ++m) {
      const double centre = peak + 2.0 * kPi * static_cast<double>(m);
      if (centre - half > span_hi + step_) break;
      long lo = std::max(first, static_cast<long>(std::ceil(step_of(centre - half))));
      long hi = std::min(last, static_cast<long>(std::floor(step_of(centre + half))));
      lo = std::max(lo, done + 1);
      if (lo > hi) {  // no step inside by the closed form: rounding may still let one in
        const long k = std::lround(step_of(centre));
        if (k < std::max(first, done + 1) || k > last || !chip_at(e, at, k)) continue;
        lo = hi = k;
      }
      // The closed form's ends agree with the test to rounding: settle them by the test.
      while (lo <= hi && !chip_at(e, at, lo)) ++lo;
      while (hi >= lo && !chip_at(e, at, hi)) --hi;
      if (lo > hi) continue;
      while (lo - 1 > done && chip_at(e, at, lo - 1)) --lo;
      while (hi + 1 <= last && chip_at(e, at, hi + 1)) ++hi;
      add_run(e, at, lo, hi);
      done = hi;
    }
  }

  // Adds the force of the element over the whole steps lo..hi, each of which cuts a chip, to the
  // difference array.
  void add_run(const Element& e, const Rotation& at, long lo, long hi) {
    cutting_ = true;
    // Each output is P + Q·a with a = f_x sin φ + f_y cos φ (see `accumulate`).
    const double fx = feed_.x(), fy = feed_.y(), b = feed_.z(), feed = c_;
    const double kt = k_.ktc * feed, kr = k_.krc * feed, ka = k_.kac * feed;
    const double pt = -kt * b * e.c1 + k_.kte * e.l, qt = kt * e.s1;
    const double pq =
        -kr * b * e.sc + k_.kre * e.s1 - ka * b * e.c2 + k_.kae * e.c1;  // q = fr_s + fa_c
    const double qq = kr * e.s2 + ka * e.sc;
    const double pz = -kr * b * e.c2 + k_.kre * e.c1 + ka * b * e.sc - k_.kae * e.s1;
    const double qz = kr * e.sc - ka * e.s2;
    const double pm = -kt * b * e.rc + k_.kte * e.r, qm = kt * e.rs;
    // F_x = −ft·cos φ − q·sin φ, F_y = ft·sin φ − q·cos φ, F_z, torque: on 1, cos φ, sin φ,
    // cos 2φ, sin 2φ (sin²φ = (1 − cos 2φ)/2, cos²φ = (1 + cos 2φ)/2, sin φ cos φ = sin 2φ/2).
    const double in_phi[4][5] = {
        {-0.5 * (qt * fy + qq * fx), -pt, -pq, 0.5 * (qq * fx - qt * fy),
         -0.5 * (qt * fx + qq * fy)},
        {0.5 * (qt * fx - qq * fy), -pq, pt, -0.5 * (qt * fx + qq * fy), 0.5 * (qt * fy - qq * fx)},
        {pz, qz * fy, qz * fx, 0.0, 0.0},
        {pm, qm * fy, qm * fx, 0.0, 0.0}};
    // In θ = φ − offset: cos φ = cos θ cos o − sin θ sin o, sin φ = sin θ cos o + cos θ sin o,
    // and the same for 2φ with 2o.
    const double so = at.sin, co = at.cos;
    const double s2o = 2.0 * so * co, c2o = co * co - so * so;
    Harmonics run{};
    for (int component = 0; component < 4; ++component) {
      const double* p = in_phi[component];
      double* h = &run[static_cast<std::size_t>(5 * component)];
      h[0] = p[0];
      h[1] = p[1] * co + p[2] * so;
      h[2] = p[2] * co - p[1] * so;
      h[3] = p[3] * c2o + p[4] * s2o;
      h[4] = p[4] * c2o - p[3] * s2o;
    }
    const int first = wrap(lo), last = wrap(hi);
    if (first <= last) {
      mark(run, first, last);
    } else {  // across θ = 2π
      mark(run, first, n_ - 1);
      mark(run, 0, last);
    }
  }

  void mark(const Harmonics& run, int first, int last) {
    if (changes_.capacity() == 0) {
      changes_.reserve(64);  // two per run
      runs_.reserve(32);
    }
    const auto index = static_cast<std::uint32_t>(runs_.size());
    runs_.push_back(run);
    changes_.push_back({first, 1, index});
    if (last + 1 == n_) return;  // past the revolution's last step
    changes_.push_back({last + 1, -1, index});
  }

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

  // The thickest chip any flute cuts on the element over the interval. f̂·n = A(φ) sin κ −
  // f_z cos κ with sin κ ≥ 0, so φ takes A's largest value A* whatever κ; over the element's κ
  // range the sinusoid A* sin κ − f_z cos κ peaks at an end or at κ* = atan2(A*, −f_z), where it
  // is √(A*² + f_z²). Without runout every flute cuts the same chip there.
  void thickest_chip(const Element& e, const Interval& in) {
    const double a = max_lateral_feed(in), fz = feed_.z();
    const double k0 = std::atan2(e.sin_kappa[0], e.cos_kappa[0]);
    const double k1 = std::atan2(e.sin_kappa[1], e.cos_kappa[1]);
    const double peak = std::atan2(a, -fz);
    const bool inside = peak > std::min(k0, k1) && peak < std::max(k0, k1);
    const int flutes = runout_.offset > 0.0 ? flutes_ : 1;
    for (int j = 0; j < flutes; ++j) {
      for (int end = 0; end < 2; ++end) {
        const double g = a * e.sin_kappa[end] - fz * e.cos_kappa[end];
        max_chip_ = std::max(max_chip_, chip(j, g, e.sin_kappa[end], e.lag));
      }
      if (inside)
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

  // One step's force of flute j on element e, at sin φ = s, cos φ = c, times `weight`.
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
  std::vector<Change> changes_;  // a difference array over the steps, sparse
  std::vector<Harmonics> runs_;  // the harmonics of each run marked
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
  if (!(options.angle_step >= kMinAngleStep) ||
      options.angle_step > kPi / 2.0 * (1.0 + tol::kRelative)) {
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
    revolution.finish();
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
