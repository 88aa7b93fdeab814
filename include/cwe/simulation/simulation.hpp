#pragma once
// The main loop (docs/architecture.md) on the tri-dexel workpiece: per move, remove the volume the
// cutter sweeps (envelope::MoveSweep, exact for linear 3-axis and 3+2 moves, subdivided within the
// tolerance otherwise) from the stock, and keep the figures a report needs.
//
// Rapid moves are simulated like feed moves (the material they hit is gone on a real machine
// too) and each rapid that removes material is recorded: on a machine it is a crash.

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/engagement/dexel_engagement.hpp"
#include "cwe/engagement/workpiece.hpp"
#include "cwe/envelope/move_sweep.hpp"
#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/io/step.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/toolpath/toolpath.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"
#include "cwe/workpiece/mesh/mesh_stock.hpp"

namespace cwe {

// Where the stock comes from: "box:xmin,ymin,zmin,xmax,ymax,zmax" (mm; in inches with a
// trailing ":in"), an STL file, or a STEP file (.step, .stp: its solids, in the file's unit).
struct StockSpec {
  bool is_box = true;
  Aabb box;
  std::string path;  // STL or STEP file when !is_box
  // The STL's triangles once read (read_stock_spec); make_stock reads the file when absent.
  std::shared_ptr<const TriangleMesh> mesh;
  // The STEP file's solids once read (read_stock_spec; the other backends take them
  // tessellated).
  std::shared_ptr<const StepModel> step;
  // An STL stock's triangles made solid, for the B-rep workpiece (prepare_job).
  std::shared_ptr<const StepModel> mesh_solid;
  bool is_step() const { return !is_box && is_step_path(path); }
};

// Parses a stock specification; `source` names where it came from in error messages.
StockSpec parse_stock_spec(const std::string& text, const SourceLocation& source);
// The same, with an STL stock's triangles read (once, for both the stock's top and make_stock).
StockSpec read_stock_spec(const std::string& text, const SourceLocation& source);
// The stock's highest point, mm (an STL stock must have been read).
double stock_top(const StockSpec& spec);
// The stock's bounding box, the domain of its rays (an STL stock must have been read).
Aabb stock_box(const StockSpec& spec);

struct SimulationOptions {
  double resolution = 0.1;  // ray spacing s, mm
  // Subdivision tolerance of arcs, helices and 5-axis moves, mm (0: resolution / 10).
  double tolerance = 0.0;
  double effective_tolerance() const { return tolerance > 0.0 ? tolerance : resolution / 10.0; }
};

// The stock as a tri-dexel workpiece: a STEP stock's solids tessellated within s/10
// (step_tessellation). Throws InputError for a bad box, an unreadable or open STL, or a
// resolution the stock cannot take.
TriDexel make_stock(const StockSpec& spec, const SimulationOptions& options);
// The stock as a closed triangle mesh (the mesh workpiece): a STEP stock's solids tessellated
// within the tolerance. Throws InputError for a bad box, or an STL that is not the closed,
// outward surface of a solid.
MeshStock make_mesh_stock(const StockSpec& spec, const SimulationOptions& options);
// How far from its solids a STEP stock's triangles may lie on each workpiece, mm: s/10 on the
// dexel one (below the rays' own error), the sweeps' tolerance on the mesh one.
double step_tessellation(const SimulationOptions& options, bool mesh_workpiece);

struct RapidCut {
  int move = 0;  // 0-based index into the toolpath
  SourceLocation location;
  double volume = 0.0;  // mm³ the rapid removed
};

struct RemovalSummary {
  // Rapid cuts listed (each is counted in rapid_cut_count): a program that crashes on every
  // line does not grow the summary.
  static constexpr std::size_t kRapidCutsKept = 1000;

  int moves = 0;
  int feed_moves = 0;
  int rapid_moves = 0;
  int cutting_moves = 0;         // moves that removed at least one cell (s³) of material
  int linear_pieces = 0;         // exact linear sweeps removed (after subdivision, per convex part)
  double deviation_bound = 0.0;  // largest Hausdorff bound of any move's sweep, mm
  std::vector<RapidCut> rapid_cuts;  // the first kRapidCutsKept
  std::size_t rapid_cut_count = 0;   // rapids that cut, all of them
  // mm³, per move: filled by the functions that take a whole Toolpath (which hold its moves
  // anyway); the move-at-a-time runs hand each move's volume to their MoveRemoved instead.
  std::vector<double> removed_by_move;
};

// Called after each move with (moves done, moves in all).
using Progress = std::function<void(std::size_t, std::size_t)>;
// Called with each move's index (from 0, in the order the moves were given) and the volume it
// removed, mm³.
using MoveRemoved = std::function<void(std::size_t, double)>;

// Removal one move at a time, for a program read move by move (memory that does not grow with
// its length): add() the moves in order, then finish(). Moves are removed in batches of about
// kBatchPieces linear pieces (one pass of the workpiece, the same result as one by one); the
// workpiece is complete after finish(). remove_toolpath is this over a Toolpath's moves.
class RemovalRun {
 public:
  static constexpr std::size_t kBatchPieces = 64;
  // `stock` and `cutter` must outlive the run.
  RemovalRun(Workpiece& stock, const Cutter& cutter, const SimulationOptions& options,
             MoveRemoved removed = {});
  // `sources` are the files the move's `source` indexes (Toolpath::sources).
  void add(const Move& move, const std::vector<std::string>& sources);
  RemovalSummary finish();

 private:
  struct Pending {
    bool rapid = false;
    SourceLocation at;  // the move's file and line (a rapid that cuts, a computation that fails)
  };
  void flush();
  Workpiece& stock_;
  ConvexParts parts_;
  MoveRemoved removed_;
  double cell_;
  RemovalSummary summary_;
  std::vector<MoveSweep> sweeps_;
  std::vector<Pending> pending_;
  std::size_t pieces_ = 0;
};

// Removes every move of `path` swept by `cutter` from `stock`, in order (batched: several moves
// to one pass of the workpiece).
RemovalSummary remove_toolpath(Workpiece& stock, const Cutter& cutter, const Toolpath& path,
                               const SimulationOptions& options, const Progress& progress = {});
// The same on the tri-dexel workpiece (DexelWorkpiece).
RemovalSummary remove_toolpath(TriDexel& stock, const Cutter& cutter, const Toolpath& path,
                               const SimulationOptions& options, const Progress& progress = {});

// What a ClPrepare made of a location, handed on with it (a derived type of the caller's).
struct ClExtra {
  virtual ~ClExtra() = default;
};

// The engagement at one cutter location, as the main job hands it on.
struct ClEngagement {
  std::size_t index;        // of the sample among all of the run's, from 0
  const Move& move;         // the move it lies on
  const std::string& file;  // the file of the move's source line ("" when it names none)
  const ClPoint& cl;
  const ToolState& state;  // the tool's state there
  const EngagementMap& map;
  const ClExtra* extra;  // what the run's ClPrepare returned (null without one)
};
// Receives the engagement at each cutter location, in order.
using EngagementSink = std::function<void(const ClEngagement&)>;
// Work at a location that needs no order (a force model's evaluation, say): called beside the
// engagement search, on any thread and several locations at once, so that the sink keeps only
// the work that must be done in order. It must not change shared state. `extra` is null.
using ClPrepare = std::function<std::unique_ptr<ClExtra>(const ClEngagement&)>;

// How the main job samples the moves and finds the engagement.
struct EngagementRunOptions {
  SimulationOptions simulation;
  SamplingOptions sampling;      // rapids are never sampled (include_rapids is ignored)
  EngagementOptions engagement;  // a contact of 0 takes the sweep tolerance
  // Cutter locations (or moves) EngagementRun holds before it runs them as one pipeline (at
  // least 1). Every result is the same for any batch; each batch starts with one thread removing
  // and ends with the others finishing, so larger batches keep the threads busier.
  std::size_t batch_locations = 2048;
  std::size_t batch_moves = 8192;
};

// The main job (simulate_engagement) one move at a time: add() the moves in order, then finish().
//
// Moves are held until about options.batch_locations cutter locations (or batch_moves moves) are
// waiting, then run as a pipeline: the steps are removed in order, a group at a time (as many as
// the workpiece removes in one pass: StepEngagement::steps_per_removal, record_bytes within
// kRecordBudget), each into a record of its own, while the engagement of the steps already
// removed is found in parallel (it reads only its step's record), and the locations go to
// `sink` in order, on one thread at a time (not necessarily the caller's). So a move's locations
// reach `sink` during a later add() or during finish(); the results are those of one step at a
// time, for any number of threads. `prepare`, when given, runs with the engagement search and its
// result reaches `sink` with the location.
class EngagementRun {
 public:
  // Bytes the records of the groups in flight may hold together (an estimate from the sweeps).
  static constexpr std::size_t kRecordBudget = std::size_t{64} << 20;
  // `stock` and `cutter` must outlive the run.
  EngagementRun(Workpiece& stock, const Cutter& cutter, const EngagementRunOptions& options,
                const EngagementSink& sink, MoveRemoved removed = {}, ClPrepare prepare = {});
  ~EngagementRun();
  EngagementRun(const EngagementRun&) = delete;
  EngagementRun& operator=(const EngagementRun&) = delete;
  void add(const Move& move, const std::vector<std::string>& sources);
  RemovalSummary finish();

 private:
  // A move waiting, with its locations (cls_[first_cl …]).
  struct PendingMove {
    Move move;
    std::size_t index = 0;  // among the run's moves
    std::size_t file = 0;   // in files_
    std::size_t first_cl = 0, cl_count = 0;
  };
  struct PendingCl {
    ClPoint cl;
    ToolState state;
  };
  void flush();
  double cell_;
  Aabb region_;  // the workpiece's (MoveSweep)
  ConvexParts parts_;
  std::unique_ptr<StepEngagement> engage_;
  ClSampler sampler_;
  EngagementSink sink_;
  MoveRemoved removed_;
  ClPrepare prepare_;
  RemovalSummary summary_;
  std::vector<ClPoint> sampled_;  // of the move being added
  std::vector<PendingMove> moves_;
  std::vector<std::string> files_;  // of the waiting moves, each name once in a row
  std::vector<PendingCl> cls_;
  // The records of each group in flight (a group's steps, in order).
  std::vector<std::vector<std::unique_ptr<StepEngagement::Step>>> steps_;
  std::size_t batch_locations_, batch_moves_;
  std::size_t added_ = 0;                                     // moves given so far
  std::size_t index_ = 0;  // of the next CL among all of the run's to be removed
  Vec3 previous_x_ = Vec3::Zero();
};

// The main job: at each cutter location of the feed moves (ClSampler, one move at a time), the
// removal of the motion up to the next location, and the engagement there: where that step's
// removal touches the cutter, the workpiece having been cut by all motion before the location
// (docs/architecture.md flow; DexelEngagement). Rapid moves and moves without samples are
// removed whole. The removal summary is that of remove_toolpath (the same workpiece results).
RemovalSummary simulate_engagement(Workpiece& stock, const Cutter& cutter, const Toolpath& path,
                                   const EngagementRunOptions& options, const EngagementSink& sink,
                                   const Progress& progress = {});
// The same on the tri-dexel workpiece (DexelWorkpiece).
RemovalSummary simulate_engagement(TriDexel& stock, const Cutter& cutter, const Toolpath& path,
                                   const EngagementRunOptions& options, const EngagementSink& sink,
                                   const Progress& progress = {});

}  // namespace cwe
