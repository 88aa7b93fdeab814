#include "cwe/geometry/mesh_sections.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cwe {
namespace {

// Items binned by position: item k lies in bins span(k).first ..= span(k).second; fills `start`
// (bins + 1 offsets) and `out` (the items of each bin, in item order).
template <class Span>
void fill_bins(std::size_t items, int bins, const Span& span, std::vector<std::uint32_t>& start,
               std::vector<std::uint32_t>& out) {
  start.assign(static_cast<std::size_t>(bins) + 1, 0);
  for (std::size_t k = 0; k < items; ++k) {
    const auto [lo, hi] = span(k);
    for (int b = lo; b <= hi; ++b) ++start[static_cast<std::size_t>(b) + 1];
  }
  for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  out.assign(start.back(), 0);
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < items; ++k) {
    const auto [lo, hi] = span(k);
    for (int b = lo; b <= hi; ++b)
      out[next[static_cast<std::size_t>(b)]++] = static_cast<std::uint32_t>(k);
  }
}

// The bin of x in [lo, lo + bins / scale): the same expression wherever a position is binned,
// so that it is monotone in x.
int bin_of(double x, double lo, double scale, int bins) {
  const double b = std::floor((x - lo) * scale);
  return b <= 0.0 ? 0 : b >= bins - 1 ? bins - 1 : static_cast<int>(b);
}

int bins_for(std::size_t items) {
  return static_cast<int>(std::clamp<std::size_t>(items / 4, 1, 256));
}

}  // namespace

void MeshSection::index() {
  if (segments_.empty()) return;
  v_min_ = segments_.front().v0;
  v_max_ = v_min_;
  for (const Segment& s : segments_) {
    v_min_ = std::min({v_min_, s.v0, s.v1});
    v_max_ = std::max({v_max_, s.v0, s.v1});
  }
  const int stripes = bins_for(segments_.size());
  per_stripe_ = v_max_ > v_min_ ? stripes / (v_max_ - v_min_) : 0.0;
  fill_bins(
      segments_.size(), stripes,
      [&](std::size_t k) {
        const Segment& s = segments_[k];
        return std::pair{bin_of(std::min(s.v0, s.v1), v_min_, per_stripe_, stripes),
                         bin_of(std::max(s.v0, s.v1), v_min_, per_stripe_, stripes)};
      },
      start_, bin_);
}

bool MeshSection::contains(double u, double v) const {
  if (segments_.empty() || !(v >= v_min_ && v < v_max_)) return false;
  const int stripes = static_cast<int>(start_.size()) - 1;
  const auto b = static_cast<std::size_t>(bin_of(v, v_min_, per_stripe_, stripes));
  bool inside = false;
  for (std::uint32_t k = start_[b]; k < start_[b + 1]; ++k) {
    const Segment& s = segments_[bin_[k]];
    if ((s.v0 > v) == (s.v1 > v)) continue;
    // The crossing of the line through v, from the segment's lower end (the same number
    // whichever way round the segment was stored).
    const bool up = s.v0 < s.v1;
    const double ua = up ? s.u0 : s.u1, va = up ? s.v0 : s.v1;
    const double ub = up ? s.u1 : s.u0, vb = up ? s.v1 : s.v0;
    if (ua + (v - va) * (ub - ua) / (vb - va) > u) inside = !inside;
  }
  return inside;
}

MeshSlicer::MeshSlicer(const TriangleMesh& mesh, const Frame& frame)
    : frame_(frame), triangles_(mesh.triangles) {
  local_.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) local_.push_back(frame.to_local(p));
  if (triangles_.empty()) return;
  std::vector<std::pair<double, double>> spans;  // each triangle's lowest and highest w
  spans.reserve(triangles_.size());
  for (const auto& t : triangles_) {
    const double a = local_[static_cast<std::size_t>(t[0])].z();
    const double b = local_[static_cast<std::size_t>(t[1])].z();
    const double c = local_[static_cast<std::size_t>(t[2])].z();
    spans.emplace_back(std::min({a, b, c}), std::max({a, b, c}));
  }
  w_min_ = spans.front().first;
  w_max_ = spans.front().second;
  for (const auto& [lo, hi] : spans) {
    w_min_ = std::min(w_min_, lo);
    w_max_ = std::max(w_max_, hi);
  }
  const int layers = bins_for(triangles_.size());
  per_layer_ = w_max_ > w_min_ ? layers / (w_max_ - w_min_) : 0.0;
  fill_bins(
      triangles_.size(), layers,
      [&](std::size_t k) {
        const auto [lo, hi] = spans[k];
        return std::pair{bin_of(lo, w_min_, per_layer_, layers),
                         bin_of(hi, w_min_, per_layer_, layers)};
      },
      start_, layer_);
}

MeshSection MeshSlicer::section(double h) const {
  MeshSection out;
  // A vertex at w ≥ h is above the lowered plane: none is below at h ≤ w_min, all are at
  // h > w_max.
  if (triangles_.empty() || !(h > w_min_ && h <= w_max_)) return out;
  const int layers = static_cast<int>(start_.size()) - 1;
  const auto layer = static_cast<std::size_t>(bin_of(h, w_min_, per_layer_, layers));
  // Where edge (a, b) crosses the plane, from its lower-numbered end: both triangles of the
  // edge get the same point.
  const auto cross = [&](int a, int b) {
    if (a > b) std::swap(a, b);
    const Vec3& p = local_[static_cast<std::size_t>(a)];
    const Vec3& q = local_[static_cast<std::size_t>(b)];
    const double t = (h - p.z()) / (q.z() - p.z());
    return Vec2(p.x() + t * (q.x() - p.x()), p.y() + t * (q.y() - p.y()));
  };
  for (std::uint32_t k = start_[layer]; k < start_[layer + 1]; ++k) {
    const auto& t = triangles_[layer_[k]];
    bool above[3];
    for (int i = 0; i < 3; ++i) {
      above[i] = local_[static_cast<std::size_t>(t[static_cast<std::size_t>(i)])].z() >= h;
    }
    if (above[0] == above[1] && above[1] == above[2]) continue;
    // The vertex alone on its side, and the two edges from it.
    const int lone = above[0] == above[1] ? 2 : above[0] == above[2] ? 1 : 0;
    const int a = t[static_cast<std::size_t>(lone)];
    const Vec2 p = cross(a, t[static_cast<std::size_t>((lone + 1) % 3)]);
    const Vec2 q = cross(a, t[static_cast<std::size_t>((lone + 2) % 3)]);
    out.segments_.push_back({p.x(), p.y(), q.x(), q.y()});
  }
  out.index();
  return out;
}

}  // namespace cwe
