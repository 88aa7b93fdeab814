#include "cwe/workpiece/dexel/removal_record.hpp"

#include <algorithm>

namespace cwe {

void RemovalRecord::clear() {
  for (auto& family : stretches_) family.clear();
}

bool RemovalRecord::empty() const {
  return std::all_of(stretches_.begin(), stretches_.end(),
                     [](const std::vector<Stretch>& family) { return family.empty(); });
}

std::span<const RemovalRecord::Stretch> RemovalRecord::on_ray(int axis, std::size_t ray) const {
  const auto& all = stretches_[static_cast<std::size_t>(axis)];
  const auto first = std::lower_bound(all.begin(), all.end(), ray,
                                      [](const Stretch& s, std::size_t r) { return s.ray < r; });
  auto last = first;
  while (last != all.end() && last->ray == ray) ++last;
  return {first, last};
}

}  // namespace cwe
