#include "cwe/workpiece/dexel/dexel_mesh.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <span>
#include <thread>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "cwe/core/assert.hpp"
#include "cwe/core/error.hpp"
#include "cwe/core/memory_limit.hpp"

namespace cwe {
namespace {

// Cube corners are numbered c = dx + 2·dy + 4·dz by their offsets from the cube's lowest
// lattice point. Cube edges are numbered 4a + ob + 2·oc: a the edge's axis, (ob, oc) the offsets
// of its lower end along the two other axes in cyclic order, b = a + 1 and c = a + 2 (mod 3).
constexpr int kCorners = 8;
constexpr int kEdges = 12;
constexpr int kCases = 1 << kCorners;  // a case: the set of corners inside
constexpr int kMaxTriangles = 10;  // loops of L crossings give L − 2 triangles; ΣL ≤ 12

// A case's triangles: the cube edges they use, each once, in the order of their first use, and
// each triangle's corners as places in that list (so that a cube looks each vertex up once, and
// makes new ones in the order the triangles first use them).
struct CubeCase {
  int triangle_count = 0;
  int edge_count = 0;
  std::array<int, kEdges> edges{};
  std::array<std::array<int, 3>, kMaxTriangles> corners{};
};

// The lattice offsets of cube edge e's lower end from the cube's lowest point, and its axis:
// edge 4a + ob + 2·oc runs along a from offset ob along a + 1 and oc along a + 2.
struct EdgeStart {
  int axis;
  std::array<int, 3> offset;
};
constexpr std::array<EdgeStart, kEdges> kEdgeStarts = [] {
  std::array<EdgeStart, kEdges> starts{};
  for (int e = 0; e < kEdges; ++e) {
    const int a = e / 4;
    std::array<int, 3> offset{0, 0, 0};
    offset[static_cast<std::size_t>((a + 1) % 3)] = e & 1;
    offset[static_cast<std::size_t>((a + 2) % 3)] = (e >> 1) & 1;
    starts[static_cast<std::size_t>(e)] = {a, offset};
  }
  return starts;
}();

int corner_bit(int corner, int axis) { return (corner >> axis) & 1; }

// The cube edge joining two corners that differ along one axis.
int edge_between(int corner0, int corner1) {
  const int differ = corner0 ^ corner1;
  CWE_ASSERT(differ == 1 || differ == 2 || differ == 4, "corners are not neighbours");
  const int a = differ == 1 ? 0 : (differ == 2 ? 1 : 2);
  const int lower = corner0 & corner1;
  return 4 * a + corner_bit(lower, (a + 1) % 3) + 2 * corner_bit(lower, (a + 2) % 3);
}

// Whether two cube edges lie on a common face (face 2·axis + side; edge 4a + ob + 2·oc lies on
// faces (a + 1, ob) and (a + 2, oc)).
bool share_face(int edge0, int edge1) {
  const auto faces = [](int e) {
    const int a = e / 4;
    return std::array<int, 2>{2 * ((a + 1) % 3) + (e & 1), 2 * ((a + 2) % 3) + ((e >> 1) & 1)};
  };
  const auto f0 = faces(edge0), f1 = faces(edge1);
  return f0[0] == f1[0] || f0[0] == f1[1] || f0[1] == f1[0] || f0[1] == f1[1];
}

// The triangles of one case (bit c of `inside` set: corner c holds material).
//
// Faces first: walking a face's corners counter-clockwise about its outward normal n, every run
// of inside corners is cut off by one segment, from the edge where the walk enters the run
// ("entry") to the edge where it leaves it ("exit"). Diagonal inside corners are two runs, so an
// ambiguous face separates them, whichever cube looks at it. The segment's direction d then
// makes n × d point from the inside corners to the outside ones.
// Each crossing edge lies on two faces that walk it in opposite directions, so it is the exit of
// one face's segment and the entry of the other's: the segments link into loops. A loop is
// filled as a fan whose right-hand normal, n × d at its rim, points out of the material.
//
// The fan's inner edges must stay private to the cube: an inner edge joining two crossings of
// one (ambiguous) face could also be an inner edge of the neighbour across that face, and then
// four triangles would share it. So the fan's apex is the first loop vertex none of whose
// diagonals joins two edges of one face. Such an apex exists in all 256 cases (loops have at
// most seven crossings); the assertion below checks it when the table is built.
CubeCase make_case(int inside) {
  std::array<int, kEdges> next{};
  next.fill(-1);
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      // (0,0), (1,0), (1,1), (0,1) in (b, c) turn counter-clockwise about e_b × e_c = e_a, the
      // outward normal of the upper face; the lower face walks them the other way.
      constexpr std::array<std::array<int, 2>, 4> kSquare{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
      std::array<int, 4> corner{};
      std::array<bool, 4> in{};
      for (std::size_t k = 0; k < 4; ++k) {
        const auto& q = kSquare[side == 1 ? k : 3 - k];
        corner[k] = (side << a) | (q[0] << b) | (q[1] << c);
        in[k] = ((inside >> corner[k]) & 1) != 0;
      }
      const auto at = [](int k) { return static_cast<std::size_t>(k & 3); };
      for (int k = 0; k < 4; ++k) {
        if (!in[at(k)] || in[at(k + 1)]) continue;
        const int exit = edge_between(corner[at(k)], corner[at(k + 1)]);
        int m = k - 1;
        while (in[at(m)]) --m;  // stops: corner k + 1 is outside
        const int entry = edge_between(corner[at(m)], corner[at(m + 1)]);
        CWE_ASSERT(next[static_cast<std::size_t>(entry)] < 0, "an edge entered twice");
        next[static_cast<std::size_t>(entry)] = exit;
      }
    }
  }
  CubeCase result;
  // The triangle with corners on cube edges e0, e1, e2.
  const auto add_triangle = [&result](int e0, int e1, int e2) {
    CWE_ASSERT(result.triangle_count < kMaxTriangles, "too many triangles in a cube");
    auto& corners = result.corners[static_cast<std::size_t>(result.triangle_count++)];
    const std::array<int, 3> edges{e0, e1, e2};
    for (std::size_t v = 0; v < 3; ++v) {
      int place = 0;
      while (place < result.edge_count &&
             result.edges[static_cast<std::size_t>(place)] != edges[v]) {
        ++place;
      }
      if (place == result.edge_count) {
        result.edges[static_cast<std::size_t>(result.edge_count++)] = edges[v];
      }
      corners[v] = place;
    }
  };
  std::array<bool, kEdges> visited{};
  for (int start = 0; start < kEdges; ++start) {
    if (next[static_cast<std::size_t>(start)] < 0 || visited[static_cast<std::size_t>(start)]) {
      continue;
    }
    std::vector<int> loop;
    for (int e = start; !visited[static_cast<std::size_t>(e)];
         e = next[static_cast<std::size_t>(e)]) {
      visited[static_cast<std::size_t>(e)] = true;
      loop.push_back(e);
    }
    const int n = static_cast<int>(loop.size());
    CWE_ASSERT(n >= 3, "a loop of fewer than three crossings");
    const auto vertex = [&loop, n](int k) { return loop[static_cast<std::size_t>(k % n)]; };
    int apex = -1;
    for (int r = 0; r < n && apex < 0; ++r) {
      bool private_diagonals = true;
      for (int k = 2; k <= n - 2; ++k) private_diagonals &= !share_face(vertex(r), vertex(r + k));
      if (private_diagonals) apex = r;
    }
    CWE_ASSERT(apex >= 0, "a loop whose fan would share an inner edge with a neighbour");
    for (int k = 1; k + 1 < n; ++k) {
      add_triangle(vertex(apex), vertex(apex + k), vertex(apex + k + 1));
    }
  }
  return result;
}

const std::array<CubeCase, kCases>& cube_cases() {
  static const std::array<CubeCase, kCases> cases = [] {
    std::array<CubeCase, kCases> all;
    for (int inside = 0; inside < kCases; ++inside) {
      all[static_cast<std::size_t>(inside)] = make_case(inside);
    }
    return all;
  }();
  return cases;
}

// The marching's spare thread (a task that another thread of the arena picks up). It faults in
// the pages of the mesh's reserved arrays (populate_pages) up to a few megabytes ahead of the
// thread that fills them in order, which then finds its pages there instead of taking each fault
// itself (in the main job's closing stage on the pocketing bench, those faults were nearly half
// of the marching's time: docs/performance.md). Behind that thread it hands the triangles made
// to a follower, if any, a run at a time (stock.stl encoded and written while the stock is
// contoured). It reads only triangles made and published (reached()) and the vertices they name,
// which the filling thread no longer writes; before the arrays would outgrow their capacity
// (reallocated), that thread stops it.
// Without a spare thread it does nothing: a task that only the filling thread picks up (at
// stop()) returns at once.
class SpareThread {
  using Triangle = std::array<int, 3>;

 public:
  SpareThread(const TriangleMesh& mesh, const MeshFollower* follow)
      : filler_(std::this_thread::get_id()),
        follow_(follow),
        triangles_(mesh.triangles.data()),
        vertices_(mesh.vertices.data()),
        triangle_bytes_(mesh.triangles.capacity() * sizeof(Triangle)),
        vertex_bytes_(mesh.vertices.capacity() * sizeof(Vec3)) {
    if (tbb::this_task_arena::max_concurrency() > 1 && triangle_bytes_ > 0) {
      work_.run([this] { run(); });
    }
  }
  SpareThread(const SpareThread&) = delete;
  SpareThread& operator=(const SpareThread&) = delete;
  ~SpareThread() {
    stopped_.store(true, std::memory_order_relaxed);
    work_.wait();  // run() throws nothing: a follower's error waits in error_
  }

  // The triangles and vertices made so far, all written.
  void reached(std::size_t triangles, std::size_t vertices) {
    vertices_made_.store(vertices, std::memory_order_relaxed);
    triangles_made_.store(triangles, std::memory_order_release);
  }
  // Ends the spare thread's work; returns once it has left the arrays, throwing the follower's
  // error if it threw one.
  void stop() {
    stopped_.store(true, std::memory_order_relaxed);
    work_.wait();
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }
  // The triangles handed to the follower (read after stop()).
  std::size_t followed() const { return followed_; }

 private:
  static constexpr std::size_t kStep = kHugePageBytes;
  static constexpr std::size_t kAhead = std::size_t{8} << 20;  // of the triangles filled
  static constexpr std::size_t kRun = 16'384;                  // triangles handed at a time

  void run() {
    if (std::this_thread::get_id() == filler_) return;
    const double vertex_share =
        static_cast<double>(vertex_bytes_) / static_cast<double>(triangle_bytes_);
    const auto vertex_at = [&](std::size_t triangle_byte) {
      return std::min(vertex_bytes_,
                      static_cast<std::size_t>(vertex_share * static_cast<double>(triangle_byte)));
    };
    const auto* triangle_bytes = reinterpret_cast<const char*>(triangles_);
    const auto* vertex_bytes = reinterpret_cast<const char*>(vertices_);
    std::size_t faulted = 0;  // bytes of the triangles' array
    bool faulting = true;
    while (!stopped_.load(std::memory_order_relaxed)) {
      const std::size_t made = triangles_made_.load(std::memory_order_acquire);
      if (faulting && faulted < triangle_bytes_ && faulted < made * sizeof(Triangle) + kAhead) {
        const std::size_t next = std::min(triangle_bytes_, faulted + kStep);
        faulting = populate_pages(triangle_bytes + faulted, next - faulted);
        populate_pages(vertex_bytes + vertex_at(faulted), vertex_at(next) - vertex_at(faulted));
        faulted = next;
      } else if (follow_ != nullptr && followed_ < made) {
        const std::size_t end = std::min(made, followed_ + kRun);
        try {
          (*follow_)(
              std::span<const Triangle>(triangles_ + followed_, end - followed_),
              std::span<const Vec3>(vertices_, vertices_made_.load(std::memory_order_relaxed)));
        } catch (...) {
          error_ = std::current_exception();
          return;
        }
        followed_ = end;
      } else if (follow_ == nullptr && (!faulting || faulted >= triangle_bytes_)) {
        return;
      } else {
        std::this_thread::sleep_for(std::chrono::microseconds(100));
      }
    }
  }

  const std::thread::id filler_;  // the thread that fills the arrays
  const MeshFollower* follow_;
  const Triangle* triangles_;
  const Vec3* vertices_;
  std::size_t triangle_bytes_, vertex_bytes_;
  std::atomic<std::size_t> triangles_made_{0}, vertices_made_{0};
  std::atomic<bool> stopped_{false};
  std::size_t followed_ = 0;
  std::exception_ptr error_;
  tbb::task_group work_;
};

// Marching cubes over the lattice g(i, j, k) = min + (f_x(i) + ½, f_y(j) + ½, f_z(k) + ½)·s, slab
// by slab along Z, where f_a(i) = offset_a + stride·i picks every stride-th ray position along axis
// a, centred in the domain. Lattice indices run from -1 to n (one padding point beyond each side of
// the domain, always empty); arrays over a layer are indexed by (i + 1) + (j + 1)·width, the width
// nx + 2 rounded up to whole 8-byte words (the extra points are padding too) so that rows are
// processed a word at a time.
//
// A point's material along one ray is the test lo ≤ (m + ½)s ≤ hi against the ray's float
// intervals, evaluated exactly alike everywhere (the layer bits and the crossings), so that the
// crossings agree with the bits whenever the ray does.
class LatticeMesher {
 public:
  LatticeMesher(const TriDexel& stock, int stride)
      : stock_(stock),
        s_(stock.spacing(0), stock.spacing(1), stock.spacing(2)),
        origin_(stock.domain().min),
        stride_(stride),
        offset_{centring(stock.grid(2)[0], stride), centring(stock.grid(2)[1], stride),
                centring(stock.grid(0)[1], stride)},
        nx_(coarse(stock.grid(2)[0], stride)),
        ny_(coarse(stock.grid(2)[1], stride)),
        nz_(coarse(stock.grid(0)[1], stride)),
        width_((static_cast<std::size_t>(nx_) + 2 + kWord - 1) / kWord * kWord),
        layer_size_(width_ * (static_cast<std::size_t>(ny_) + 2)),
        toggles_(layer_size_, 0),
        running_(width_ / kWord, 0),
        z_inside_(layer_size_, 0),
        z_vertex_(layer_size_) {
    CWE_ASSERT(stock.grid(0)[0] == stock.grid(2)[1] && stock.grid(1)[0] == stock.grid(0)[1] &&
                   stock.grid(1)[1] == stock.grid(2)[0],
               "the three ray families span different lattices");
  }

  FollowedMesh run(const MeshFollower* follow) {
    const auto& cases = cube_cases();
    collect_z_events();
    reserve();
    SpareThread spare(mesh_, follow);
    spare_ = &spare;
    Layer lower(layer_size_), upper(layer_size_);  // lower starts as the empty layer -1
    for (int k = -1; k < nz_; ++k) {               // the slab between layers k and k + 1
      spare.reached(mesh_.triangles.size(), mesh_.vertices.size());
      fill_layer(k + 1, upper);
      z_vertex_.reset();
      const std::array<Layer*, 2> slab{&lower, &upper};
      for (int j = -1; j < ny_; ++j) {
        const std::uint8_t* l0 = &lower.inside[point(-1, j)];
        const std::uint8_t* l1 = l0 + width_;
        const std::uint8_t* u0 = &upper.inside[point(-1, j)];
        const std::uint8_t* u1 = u0 + width_;
        for (int i = -1; i < nx_;) {
          const auto x = static_cast<std::size_t>(i + 1);
          // Eight points alike in all four rows: the seven cubes between them are all empty or
          // all full (most of a stock is).
          if (x + 8 <= width_ && alike(l0 + x, l1 + x, u0 + x, u1 + x)) {
            i += 7;
            continue;
          }
          const int inside = l0[x] | l0[x + 1] << 1 | l1[x] << 2 | l1[x + 1] << 3 | u0[x] << 4 |
                             u0[x + 1] << 5 | u1[x] << 6 | u1[x + 1] << 7;
          if (inside != 0 && inside != kCases - 1) {
            const CubeCase& cube = cases[static_cast<std::size_t>(inside)];
            std::array<int, kEdges> made{};
            for (int e = 0; e < cube.edge_count; ++e) {
              made[static_cast<std::size_t>(e)] =
                  vertex(cube.edges[static_cast<std::size_t>(e)], i, j, k, slab);
            }
            for (int t = 0; t < cube.triangle_count; ++t) {
              const auto& corners = cube.corners[static_cast<std::size_t>(t)];
              if (mesh_.triangles.size() == mesh_.triangles.capacity()) spare.stop();
              mesh_.triangles.push_back({made[static_cast<std::size_t>(corners[0])],
                                         made[static_cast<std::size_t>(corners[1])],
                                         made[static_cast<std::size_t>(corners[2])]});
            }
          }
          ++i;
        }
      }
      std::swap(lower, upper);
    }
    spare.stop();
    spare_ = nullptr;
    return {std::move(mesh_), spare.followed()};
  }

 private:
  // Vertex indices on the lattice edges of one kind (along X or Y in a layer, along Z in a slab)
  // by the edge's lower point, -1 until made. Reset by undoing only the entries set, so a layer
  // costs its crossings, not its points.
  struct EdgeVertices {
    explicit EdgeVertices(std::size_t size) : index(size, -1) {}
    void reset() {
      for (const std::size_t p : touched) index[p] = -1;
      touched.clear();
    }
    std::vector<int> index;
    std::vector<std::size_t> touched;
  };

  struct Layer {
    explicit Layer(std::size_t size) : inside(size, 0), x_vertex(size), y_vertex(size) {}
    std::vector<std::uint8_t> inside;  // 1 where the point holds material
    EdgeVertices x_vertex;             // on the edge from the point along +X
    EdgeVertices y_vertex;             // along +Y
  };

  static constexpr std::size_t kWord = sizeof(std::uint64_t);
  static constexpr std::uint64_t kAllOnes = 0x0101010101010101u;

  static void add_word(std::uint8_t* bytes, std::uint64_t addend) {
    std::uint64_t word = 0;
    std::memcpy(&word, bytes, kWord);
    word += addend;
    std::memcpy(bytes, &word, kWord);
  }

  static bool alike(const std::uint8_t* a, const std::uint8_t* b, const std::uint8_t* c,
                    const std::uint8_t* d) {
    std::uint64_t wa = 0, wb = 0, wc = 0, wd = 0;
    std::memcpy(&wa, a, sizeof wa);
    std::memcpy(&wb, b, sizeof wb);
    std::memcpy(&wc, c, sizeof wc);
    std::memcpy(&wd, d, sizeof wd);
    return wa == wb && wa == wc && wa == wd && (wa == 0 || wa == kAllOnes);
  }

  // Lattice points along an axis with n ray positions: every stride-th, centred.
  static int coarse(int n, int stride) { return (n - 1) / stride + 1; }
  static int centring(int n, int stride) { return ((n - 1) % stride) / 2; }
  // The ray position (index in the stock's grid) of lattice index `index` along `axis`.
  int fine(int axis, int index) const {
    return offset_[static_cast<std::size_t>(axis)] + stride_ * index;
  }
  // The ray coordinate of lattice index `index` along `axis`.
  double lattice_t(int axis, int index) const { return (fine(axis, index) + 0.5) * s_[axis]; }
  int count(int axis) const { return axis == 0 ? nx_ : (axis == 1 ? ny_ : nz_); }

  std::size_t point(int i, int j) const {
    return static_cast<std::size_t>(i + 1) + static_cast<std::size_t>(j + 1) * width_;
  }

  // The lattice indices m in [0, n) along `axis` with lo ≤ lattice_t(axis, m) ≤ hi, as
  // [first, end). The guesses from division are corrected by the exact test, which is the one
  // the crossings use.
  std::array<int, 2> span(const Interval& interval, int axis) const {
    const int n = count(axis);
    const double offset = offset_[static_cast<std::size_t>(axis)];
    const auto guess = [n](double m) {
      return static_cast<int>(std::clamp(m, 0.0, static_cast<double>(n)));
    };
    int first = guess(std::ceil((interval.lo / s_[axis] - 0.5 - offset) / stride_));
    while (first > 0 && lattice_t(axis, first - 1) >= interval.lo) --first;
    while (first < n && lattice_t(axis, first) < interval.lo) ++first;
    int end = guess(std::floor((interval.hi / s_[axis] - 0.5 - offset) / stride_) + 1);
    while (end > 0 && lattice_t(axis, end - 1) > interval.hi) --end;
    while (end < n && lattice_t(axis, end) <= interval.hi) ++end;
    return {first, std::max(first, end)};
  }

  // Z rays cross every layer: their state flips at the layers where an interval starts and
  // after the one where it ends. The flips are bucketed by layer (two per interval), each bucket
  // in the order of the rows j and then i. Two passes over the rows, each on all threads in
  // blocks of rows: one counts each block's flips per layer, the other puts them in place, a
  // block's after those of the blocks before it.
  void collect_z_events() {
    const auto layers = static_cast<std::size_t>(nz_);
    const auto for_each_flip = [this](int j0, int j1, const auto& visit) {
      for (int j = j0; j < j1; ++j) {
        const std::span<const DexelRay> rays = stock_.row(2, fine(1, j));
        for (int i = 0; i < nx_; ++i) {
          const DexelRay& ray = rays[static_cast<std::size_t>(fine(0, i))];
          for (int m = 0; m < ray.count(); ++m) {
            const auto [first, end] = span(ray.interval(m), 2);
            if (first == end) continue;
            visit(first, point(i, j));
            if (end < nz_) visit(end, point(i, j));
          }
        }
      }
    };
    constexpr int kBlockRows = 16;
    const int blocks = (ny_ + kBlockRows - 1) / kBlockRows;
    const auto rows_of = [this](int block) {
      return std::array<int, 2>{block * kBlockRows, std::min(ny_, (block + 1) * kBlockRows)};
    };
    // at[b][k]: where block b's flips of layer k go (counted first).
    std::vector<std::vector<std::size_t>> at(static_cast<std::size_t>(blocks),
                                             std::vector<std::size_t>(layers, 0));
    tbb::parallel_for(0, blocks, [&](int block) {
      std::vector<std::size_t>& count = at[static_cast<std::size_t>(block)];
      const auto [j0, j1] = rows_of(block);
      for_each_flip(j0, j1, [&](int k, std::size_t) { ++count[static_cast<std::size_t>(k)]; });
    });
    z_event_start_.assign(layers + 1, 0);
    for (std::size_t k = 0; k < layers; ++k) {
      std::size_t next = z_event_start_[k];
      for (std::vector<std::size_t>& block : at) {
        const std::size_t count = block[k];
        block[k] = next;
        next += count;
      }
      z_event_start_[k + 1] = next;
    }
    z_events_.resize(z_event_start_.back());
    tbb::parallel_for(0, blocks, [&](int block) {
      std::vector<std::size_t>& fill = at[static_cast<std::size_t>(block)];
      const auto [j0, j1] = rows_of(block);
      for_each_flip(j0, j1, [&](int k, std::size_t p) {
        z_events_[fill[static_cast<std::size_t>(k)]++] = p;
      });
    });
  }

  // Room for the whole mesh at once: grown by doubling, it was copied and its pages faulted in
  // again. Each crossing of a lattice ray with the surface (an interval end) crosses a lattice
  // cell, which gives about two triangles, and a closed mesh has about half as many vertices as
  // triangles; the cells along edges and corners of the surface give more: 2.1 triangles per
  // crossing on a pocketed block, 2.5–2.65 on a ball's finishing passes, the 5-axis example and
  // FreeCAD's programs (docs/performance.md, twentieth pass). So 3.5 are reserved. Where rays of
  // two or three families cross the surface this asks for more than is used, which costs address
  // space only: pages never written are never mapped (the spare thread faults them in only a few
  // megabytes ahead of the marching).
  void reserve() {
    // The X and Y rays' ends, counted layer by layer on all threads (whole numbers: the same sum
    // in any order), then the Z rays' (their flips); as the reduction's starting value, these were
    // counted again for every block of layers it made, a different sum on each number of threads.
    const std::size_t layer_ends = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, nz_), std::size_t{0},
        [this](const tbb::blocked_range<int>& layers, std::size_t sum) {
          for (int k = layers.begin(); k < layers.end(); ++k) {
            const std::span<const DexelRay> x_rays = stock_.row(0, fine(2, k));
            for (int j = 0; j < ny_; ++j) {
              sum += 2 *
                     static_cast<std::size_t>(x_rays[static_cast<std::size_t>(fine(1, j))].count());
            }
            for (int i = 0; i < nx_; ++i) sum += 2 * stock_.at(1, fine(2, k), fine(0, i)).count();
          }
          return sum;
        },
        std::plus<>());
    const std::size_t ends = layer_ends + z_events_.size();
    mesh_.triangles.reserve(ends / 2 * 7);
    mesh_.vertices.reserve(ends / 4 * 7);
    advise_huge_pages(mesh_.triangles.data(),
                      mesh_.triangles.capacity() * sizeof(mesh_.triangles[0]));
    advise_huge_pages(mesh_.vertices.data(), mesh_.vertices.capacity() * sizeof(Vec3));
  }

  // The bits of layer k: the two-of-three vote of the rays through each point, padding empty.
  void fill_layer(int k, Layer& layer) {
    layer.x_vertex.reset();
    layer.y_vertex.reset();
    std::uint8_t* votes = layer.inside.data();
    std::fill(layer.inside.begin(), layer.inside.end(), std::uint8_t{0});
    if (k < 0 || k >= nz_) return;
    // X rays (j, k) lie in the layer along its rows: count their spans directly, eight points a
    // word where they can (the layer is zero here, so no byte carries).
    const std::span<const DexelRay> x_rays = stock_.row(0, fine(2, k));
    for (int j = 0; j < ny_; ++j) {
      const DexelRay& ray = x_rays[static_cast<std::size_t>(fine(1, j))];
      std::uint8_t* row = votes + point(0, j);
      for (int m = 0; m < ray.count(); ++m) {
        const auto [first, end] = span(ray.interval(m), 0);
        int i = first;
        for (; i + static_cast<int>(kWord) <= end; i += static_cast<int>(kWord)) {
          add_word(row + i, kAllOnes);
        }
        for (; i < end; ++i) ++row[i];
      }
    }
    // Y rays (k, i) run across the rows: mark where each span starts and ends, then carry the
    // state from row to row (reading the marks clears them for the next layer).
    for (int i = 0; i < nx_; ++i) {
      const DexelRay& ray = stock_.at(1, fine(2, k), fine(0, i));
      for (int m = 0; m < ray.count(); ++m) {
        const auto [first, end] = span(ray.interval(m), 1);
        if (first == end) continue;
        toggles_[point(i, first)] ^= 1;
        toggles_[point(i, end)] ^= 1;  // row ny is padding, never counted
      }
    }
    // Bytes hold 0 to 3 here, so eight of them add as one word without carries.
    std::fill(running_.begin(), running_.end(), std::uint64_t{0});
    for (int j = 0; j <= ny_; ++j) {
      std::uint8_t* marks = &toggles_[point(-1, j)];
      std::uint8_t* row = votes + point(-1, j);
      for (std::size_t w = 0; w < running_.size(); ++w) {
        std::uint64_t flips = 0;
        std::memcpy(&flips, marks + kWord * w, kWord);
        running_[w] ^= flips;
        if (j < ny_) add_word(row + kWord * w, running_[w]);
      }
      std::fill(marks, marks + width_, std::uint8_t{0});
    }
    // Z rays: apply this layer's flips, then add their state and take the vote (bit 1 of a
    // count from 0 to 3 says "two or more").
    const auto kk = static_cast<std::size_t>(k);
    for (std::size_t e = z_event_start_[kk]; e < z_event_start_[kk + 1]; ++e) {
      z_inside_[z_events_[e]] ^= 1;
    }
    for (std::size_t p = 0; p < layer_size_; p += kWord) {
      std::uint64_t count = 0, z = 0;
      std::memcpy(&count, votes + p, kWord);
      std::memcpy(&z, &z_inside_[p], kWord);
      count = ((count + z) >> 1) & kAllOnes;
      std::memcpy(votes + p, &count, kWord);
    }
  }

  // The ray coordinate of the vertex on the lattice edge from index m to m + 1 of `ray`, whose
  // lower end has bit `inside0` and upper end the other bit: the ray's first material boundary
  // at or after the lower end when the ray agrees with both bits, else the edge's midpoint.
  double crossing(const DexelRay& ray, int axis, int m, bool inside0) const {
    const double t0 = lattice_t(axis, m), t1 = lattice_t(axis, m + 1);
    const int count = ray.count();
    int index = 0;
    while (index < count && ray.interval(index).hi < t0) ++index;
    bool ray_inside0 = false, ray_inside1 = false;
    double boundary = t0;
    if (index < count) {
      const Interval first = ray.interval(index);
      ray_inside0 = first.lo <= t0;
      boundary = ray_inside0 ? first.hi : first.lo;
      while (index < count && ray.interval(index).hi < t1) ++index;
      ray_inside1 = index < count && ray.interval(index).lo <= t1;
    }
    // The vote overruled this ray at one end: its boundary may lie outside the edge.
    if (ray_inside0 != inside0 || ray_inside1 == inside0) return 0.5 * (t0 + t1);
    return std::clamp(boundary, t0, t1);  // already inside; the clamp only guards rounding
  }

  // The index of the vertex on cube edge `edge` of the cube whose lowest point is (i, j, k),
  // made on first use. A crossing edge never runs through padding across its axis (both its
  // ends would be empty), so its ray exists.
  int vertex(int edge, int i, int j, int k, const std::array<Layer*, 2>& slab) {
    const EdgeStart& start = kEdgeStarts[static_cast<std::size_t>(edge)];
    const int a = start.axis;
    const std::array<int, 3> p{i + start.offset[0], j + start.offset[1],
                               k + start.offset[2]};  // the edge's lower end
    Layer& layer = *slab[static_cast<std::size_t>(start.offset[2])];
    const std::size_t at = point(p[0], p[1]);
    EdgeVertices& edges = a == 0 ? layer.x_vertex : (a == 1 ? layer.y_vertex : z_vertex_);
    int& slot = edges.index[at];
    if (slot >= 0) return slot;

    const bool inside0 = layer.inside[at] != 0;
    double t = 0.0;
    if (a == 0) {
      t = crossing(stock_.at(0, fine(1, p[1]), fine(2, p[2])), 0, p[0], inside0);
    } else if (a == 1) {
      t = crossing(stock_.at(1, fine(2, p[2]), fine(0, p[0])), 1, p[1], inside0);
    } else {
      t = crossing(stock_.at(2, fine(0, p[0]), fine(1, p[1])), 2, p[2], inside0);
    }
    Vec3 position;
    for (int axis = 0; axis < 3; ++axis) {
      position[axis] =
          origin_[axis] + (axis == a ? t : lattice_t(axis, p[static_cast<std::size_t>(axis)]));
    }
    if (mesh_.vertices.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw InputError("dexel mesh: more than 2^31 vertices; export at a coarser spacing");
    }
    slot = static_cast<int>(mesh_.vertices.size());
    edges.touched.push_back(at);
    if (mesh_.vertices.size() == mesh_.vertices.capacity()) spare_->stop();
    mesh_.vertices.push_back(position);
    return slot;
  }

  const TriDexel& stock_;
  Vec3 s_;  // the stock's cell side per axis
  Vec3 origin_;
  int stride_;                              // lattice spacing in ray spacings
  std::array<int, 3> offset_;               // ray position of lattice index 0 per axis
  int nx_, ny_, nz_;                        // lattice points inside the domain per axis
  std::size_t width_;                       // padded points along X: nx + 2 or up to 7 more
  std::size_t layer_size_;                  // (nx + 2)(ny + 2)
  std::vector<std::uint8_t> toggles_;       // Y span ends in the layer being filled
  std::vector<std::uint64_t> running_;      // Y ray states along the current row, 8 a word
  std::vector<std::uint8_t> z_inside_;      // Z ray state at the current layer, by point
  std::vector<std::size_t> z_event_start_;  // flips of layer k: [start[k], start[k + 1])
  std::vector<std::size_t> z_events_;       // the points whose Z ray flips
  EdgeVertices z_vertex_;                   // on the edges from layer k to k + 1
  TriangleMesh mesh_;
  SpareThread* spare_ = nullptr;  // while run() makes mesh_
};

}  // namespace

TriangleMesh dexel_mesh(const TriDexel& stock, int stride) {
  return dexel_mesh(stock, stride, nullptr).mesh;
}

FollowedMesh dexel_mesh(const TriDexel& stock, int stride, const MeshFollower& follow) {
  if (stride < 1) {
    throw InputError(fmt::format("dexel mesh stride {}: expected a whole number ≥ 1", stride));
  }
  return LatticeMesher(stock, stride).run(follow ? &follow : nullptr);
}

int dexel_mesh_stride(const TriDexel& stock, std::size_t triangle_budget) {
  // Every material boundary on a ray is a surface crossing; a lattice cell the surface passes
  // through gives about two triangles and is crossed by about one ray of the three families
  // (exactly one for faces square to an axis), so a stride-k lattice gives about
  // 2 × crossings / k² triangles.
  // Counted row by row on all threads (whole numbers: the same sum in any order).
  const int rows0 = stock.grid(0)[1], rows1 = stock.grid(1)[1],
            rows = rows0 + rows1 + stock.grid(2)[1];
  const auto crossings = static_cast<double>(tbb::parallel_reduce(
      tbb::blocked_range<int>(0, rows), std::size_t{0},
      [&](const tbb::blocked_range<int>& range, std::size_t sum) {
        for (int r = range.begin(); r < range.end(); ++r) {
          const int a = r < rows0 ? 0 : (r < rows0 + rows1 ? 1 : 2);
          const int j = r - (a == 0 ? 0 : (a == 1 ? rows0 : rows0 + rows1));
          for (const DexelRay& ray : stock.row(a, j)) {
            sum += 2 * static_cast<std::size_t>(ray.count());
          }
        }
        return sum;
      },
      std::plus<>()));
  const double budget = std::max<double>(1.0, static_cast<double>(triangle_budget));
  return std::max(1, static_cast<int>(std::ceil(std::sqrt(2.0 * crossings / budget))));
}

}  // namespace cwe
