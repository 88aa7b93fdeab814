#include "cwe/geometry/triangle_mesh.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>

#include "cwe/core/error.hpp"

namespace cwe {

double TriangleMesh::volume() const {
  double six_v = 0.0;
  for (const auto& t : triangles) {
    const Vec3& a = vertices[static_cast<std::size_t>(t[0])];
    const Vec3& b = vertices[static_cast<std::size_t>(t[1])];
    const Vec3& c = vertices[static_cast<std::size_t>(t[2])];
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

double TriangleMesh::area() const {
  double twice = 0.0;
  for (const auto& t : triangles) {
    const Vec3& a = vertices[static_cast<std::size_t>(t[0])];
    twice += (vertices[static_cast<std::size_t>(t[1])] - a)
                 .cross(vertices[static_cast<std::size_t>(t[2])] - a)
                 .norm();
  }
  return twice / 2.0;
}

Aabb TriangleMesh::bounds() const {
  Aabb box;
  for (const Vec3& v : vertices) box.extend(v);
  return box;
}

void TriangleMesh::append(const TriangleMesh& other) {
  const int offset = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& t : other.triangles)
    triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
}

std::string MeshClosure::problem() const {
  std::string text;
  const auto list = [&text](int count, const char* what, const std::vector<Edge>& examples) {
    if (count == 0) return;
    if (!text.empty()) text += "; ";
    text += fmt::format("{} {}", count, what);
    for (std::size_t k = 0; k < examples.size(); ++k) {
      const auto& e = examples[k];
      text += fmt::format("{}({:g}, {:g}, {:g})–({:g}, {:g}, {:g})", k == 0 ? " at " : ", ",
                          e[0].x(), e[0].y(), e[0].z(), e[1].x(), e[1].y(), e[1].z());
    }
    if (count > static_cast<int>(examples.size())) text += ", …";
  };
  list(boundary_edges, "boundary edges (used by one triangle: the mesh has holes)",
       boundary_examples);
  list(non_manifold_edges, "non-manifold edges (used by three or more triangles)",
       non_manifold_examples);
  list(misoriented_edges, "edges used twice in the same direction (inconsistent winding)",
       misoriented_examples);
  return text;
}

std::vector<TriangleMesh> edge_connected_parts(const TriangleMesh& mesh) {
  std::vector<int> parent(mesh.triangles.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&parent](int t) {
    while (parent[static_cast<std::size_t>(t)] != t) {
      t = parent[static_cast<std::size_t>(t)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(t)])];
    }
    return t;
  };
  std::unordered_map<std::uint64_t, int> first;  // edge → a triangle on it
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& v = mesh.triangles[t];
    for (std::size_t k = 0; k < 3; ++k) {
      const auto [it, inserted] =
          first.try_emplace(edge_key(v[k], v[(k + 1) % 3]), static_cast<int>(t));
      if (!inserted) parent[static_cast<std::size_t>(root(static_cast<int>(t)))] = root(it->second);
    }
  }
  std::vector<TriangleMesh> parts;
  std::unordered_map<int, std::size_t> part_of;          // root → part
  std::vector<std::unordered_map<int, int>> renumbered;  // per part: mesh vertex → its own
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto [it, inserted] = part_of.try_emplace(root(static_cast<int>(t)), parts.size());
    if (inserted) {
      parts.emplace_back();
      renumbered.emplace_back();
    }
    TriangleMesh& part = parts[it->second];
    std::array<int, 3> own{};
    for (std::size_t k = 0; k < 3; ++k) {
      const int v = mesh.triangles[t][k];
      const auto [at, added] =
          renumbered[it->second].try_emplace(v, static_cast<int>(part.vertices.size()));
      if (added) part.vertices.push_back(mesh.vertices[static_cast<std::size_t>(v)]);
      own[k] = at->second;
    }
    part.triangles.push_back(own);
  }
  return parts;
}

void require_closed_stock(const TriangleMesh& mesh, const std::string& source) {
  const SourceLocation where{source};
  if (mesh.triangles.empty()) throw InputError(where, "stock mesh has no triangles");
  const MeshClosure closure = check_closure(mesh);
  if (!closure.closed()) {
    throw InputError(where, fmt::format("stock mesh is not closed: {}; expected a watertight, "
                                        "consistently oriented mesh",
                                        closure.problem()));
  }
}

MeshClosure check_closure(const TriangleMesh& mesh) {
  // Directed edge counts per undirected edge: (forward uses, backward uses).
  std::map<std::pair<int, int>, std::pair<int, int>> uses;
  for (const auto& t : mesh.triangles) {
    for (int i = 0; i < 3; ++i) {
      const int a = t[static_cast<std::size_t>(i)];
      const int b = t[static_cast<std::size_t>((i + 1) % 3)];
      auto& u = uses[{std::min(a, b), std::max(a, b)}];
      (a < b ? u.first : u.second) += 1;
    }
  }
  MeshClosure c;
  c.edges = static_cast<int>(uses.size());
  const auto keep = [&mesh](std::vector<MeshClosure::Edge>& examples, std::pair<int, int> edge) {
    if (static_cast<int>(examples.size()) >= MeshClosure::kMaxExamples) return;
    const auto n = static_cast<int>(mesh.vertices.size());
    if (edge.first < 0 || edge.second >= n) return;  // no location for an index out of range
    examples.push_back({mesh.vertices[static_cast<std::size_t>(edge.first)],
                        mesh.vertices[static_cast<std::size_t>(edge.second)]});
  };
  for (const auto& [edge, u] : uses) {
    const int total = u.first + u.second;
    if (total == 1) {
      ++c.boundary_edges;
      keep(c.boundary_examples, edge);
    }
    if (total > 2) {
      ++c.non_manifold_edges;
      keep(c.non_manifold_examples, edge);
    }
    if (total == 2 && u.first != 1) {
      ++c.misoriented_edges;
      keep(c.misoriented_examples, edge);
    }
  }
  return c;
}

int remove_folds(TriangleMesh& mesh) {
  // Each triangle by its sorted vertices, with its facing: +1 for a turn of (a, b, c), -1 for a
  // turn of (a, c, b).
  std::map<std::array<int, 3>, std::vector<std::pair<std::size_t, int>>> by_vertices;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::array<int, 3>& tri = mesh.triangles[t];
    std::array<int, 3> sorted = tri;
    std::sort(sorted.begin(), sorted.end());
    const int first = static_cast<int>(std::find(tri.begin(), tri.end(), sorted[0]) - tri.begin());
    const int facing = tri[static_cast<std::size_t>((first + 1) % 3)] == sorted[1] ? 1 : -1;
    by_vertices[sorted].push_back({t, facing});
  }
  std::vector<bool> removed(mesh.triangles.size(), false);
  int count = 0;
  for (const auto& [vertices, uses] : by_vertices) {
    std::vector<std::size_t> up, down;
    for (const auto& [t, facing] : uses) (facing > 0 ? up : down).push_back(t);
    for (std::size_t k = 0; k < std::min(up.size(), down.size()); ++k) {
      removed[up[k]] = removed[down[k]] = true;
      count += 2;
    }
  }
  if (count == 0) return 0;
  std::vector<std::array<int, 3>> kept;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!removed[t]) kept.push_back(mesh.triangles[t]);
  }
  mesh.triangles = std::move(kept);
  return count;
}

}  // namespace cwe
