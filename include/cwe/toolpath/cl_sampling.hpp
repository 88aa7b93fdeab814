#pragma once
// Cutter-location (CL) points along the feed moves of a toolpath: where engagement is evaluated.
//
// Each feed move is cut into n equal steps in u, n = max(⌈length / step⌉, ⌈axis turn /
// angular_step⌉, 1), and sampled at the start of every step, u = k/n for k = 0 … n - 1: the
// engagement at a sample sees the workpiece as cut up to that sample, and the step that follows
// is then removed (docs/architecture.md, the data flow). Zero-length moves that do not turn the
// axis give no sample. Rapid moves are skipped unless asked for.

#include <cstddef>
#include <vector>

#include "cwe/toolpath/toolpath.hpp"

namespace cwe {

struct ClPoint {
  Vec3 position = Vec3::Zero();          // tool tip, mm
  Vec3 axis = Vec3::UnitZ();             // unit, tip to shank
  Vec3 feed_direction = Vec3::Zero();    // unit tip velocity direction; zero when the tip rests
  Vec3 velocity = Vec3::Zero();          // tip velocity, mm/s
  Vec3 angular_velocity = Vec3::Zero();  // rad/s, ṅ = ω × n
  int move = 0;                          // index into Toolpath::moves
  int line = 0;                          // source line of the move
  double u = 0.0;                        // move parameter of the sample
  double path_length = 0.0;              // tip distance along the sampled moves so far, mm
};

struct SamplingOptions {
  double step = 0.5;                        // mm along the tip path (> 0)
  double angular_step = 1.0 * kPi / 180.0;  // rad of tool-axis turn (> 0)
  bool include_rapids = false;
};

// The default CL step for a tool of diameter D: 0.5 mm or D/20, the smaller.
double default_cl_step(double tool_diameter);

// Samples the moves of a toolpath one at a time, in order, so that a long program needs memory
// for one move's samples only.
class ClSampler {
 public:
  // Throws InputError when a step is not positive.
  explicit ClSampler(const SamplingOptions& options);

  // At most this many samples in one move (their memory is held together, ~150 bytes each).
  static constexpr double kMostPerMove = 1e6;
  // How many samples a move gets (0 for a rapid unless rapids are included, and for a move that
  // neither moves nor turns). Throws InputError at the move's line (in `sources`, when given)
  // when that is more than kMostPerMove.
  int steps(const Move& move, const std::vector<std::string>* sources = nullptr) const;
  // Replaces `out` with the samples of `move`, index `index` in its toolpath; moves must come in
  // order (the path length runs on from the moves before).
  void next(const Move& move, int index, std::vector<ClPoint>& out);

 private:
  SamplingOptions options_;
  double path_length_ = 0.0;
};

// Every CL point of the toolpath. Throws InputError when a step is not positive.
std::vector<ClPoint> sample_cl_points(const Toolpath& path, const SamplingOptions& options = {});
// How many that gives, without making them; throws InputError for a move with too many.
std::size_t count_cl_points(const Toolpath& path, const SamplingOptions& options = {});

}  // namespace cwe
