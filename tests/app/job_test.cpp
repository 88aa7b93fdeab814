// The job reads its programs move by move (for_each_move): the operations' moves are the
// program's, cut at its tool changes, with the tool changes' rapids between them.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/job/job.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"

namespace cwe {
namespace {

std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("cwe-job-test-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Two tools; the second tool's part begins with an arc (the tool change's rapid goes to its
// start) and the first tool's with lines (its first move starts at the change position).
constexpr const char* kProgram =
    "G21 G90 G17\n"
    "G0 X1 Y2 Z3\n"  // before the first tool change: the first tool's
    "T1 M6\nS10000 M3\nG0 X-10 Y10 Z1\nG1 Z-3 F300\nG1 X60 F600\nG0 Z5\n"
    "T2 M6\nS12000 M3\nG2 X70 Y10 I5 J0 F400\nG1 Z-2\nG1 X40\nG0 Z5\n"
    "T1 M6\nG0 X0 Y0\nG1 Z-1\nG0 Z5\n"
    "M2\n";

Job job_on(const std::filesystem::path& dir) {
  std::ofstream(dir / "p.ngc") << kProgram;
  std::ofstream(dir / "table.json") << R"({"1": "flat:10,20", "2": "ball:6,20"})";
  Job job;
  job.stock = "box:0,0,-10,50,20,0";
  job.path = (dir / "p.ngc").string();
  job.tools = (dir / "table.json").string();
  job.resolution = 0.5;
  job.cl_step = 0.7;
  return job;
}

struct Replayed {
  std::vector<std::vector<Move>> moves;  // per operation
};

Replayed replay(const PreparedJob& prepared) {
  Replayed r;
  OperationVisitor visitor;
  visitor.begin = [&](std::size_t o) {
    EXPECT_EQ(o, r.moves.size());
    r.moves.emplace_back();
  };
  visitor.move = [&](const Move& m, const std::vector<std::string>&) {
    r.moves.back().push_back(m);
  };
  visitor.end = [&](std::size_t o) { EXPECT_EQ(o + 1, r.moves.size()); };
  for_each_move(prepared, visitor);
  return r;
}

TEST(JobMoves, OperationsAreTheProgramsMovesCutAtToolChanges) {
  const auto dir = scratch_dir("replay");
  Job job = job_on(dir);
  const PreparedJob prepared = prepare_job(job);
  ASSERT_EQ(prepared.operations.size(), 3u);
  EXPECT_EQ(prepared.operations[0].tool, 1);
  EXPECT_EQ(prepared.operations[1].tool, 2);
  EXPECT_EQ(prepared.operations[2].tool, 1);
  const Replayed r = replay(prepared);
  ASSERT_EQ(r.moves.size(), 3u);

  // The program read whole, from where the job starts its tool.
  const ReadToolpath whole =
      read_toolpath_file((dir / "p.ngc").string(), prepared.operations[0].gcode);
  const std::vector<Move>& program = whole.toolpath.moves;
  std::size_t next = 0;  // the program's next move
  std::size_t cls = 0;
  for (std::size_t o = 0; o < 3; ++o) {
    const PreparedOperation& op = prepared.operations[o];
    const OperationMoves& stretch = op.moves;
    ASSERT_EQ(r.moves[o].size(), stretch.size());
    EXPECT_EQ(stretch.first, next);
    for (std::size_t i = 0; i < stretch.count; ++i) {
      const Move& got = r.moves[o][stretch.lead_in.size() + i];
      const Move& want = program[stretch.first + i];
      EXPECT_EQ(got.line, want.line) << o << " " << i;
      EXPECT_EQ(got.end, want.end) << o << " " << i;
      EXPECT_EQ(got.tool == 0 ? op.tool : got.tool, op.tool) << "line " << got.line;
      if (i > 0 || !stretch.first_start) {
        EXPECT_EQ(got.start, want.start) << "line " << got.line;
      }
    }
    next += stretch.count;
    // Each operation's CLs as counted in preparing it.
    const ClSampler sampler(op.sampling);
    std::size_t op_cls = 0;
    for (const Move& m : r.moves[o]) op_cls += static_cast<std::size_t>(sampler.steps(m));
    EXPECT_EQ(op.cl_points, op_cls) << o;
    cls += op_cls;
  }
  EXPECT_EQ(next, program.size());
  EXPECT_EQ(prepared.cl_count, cls);
  EXPECT_EQ(move_count(prepared), r.moves[0].size() + r.moves[1].size() + r.moves[2].size());

  // Tool changes: the old tool goes up to 5 mm above the stock, then across; the moves are
  // continuous across the change.
  for (std::size_t o = 0; o + 1 < 3; ++o) {
    const std::vector<Move>& out = prepared.operations[o].moves.lead_out;
    ASSERT_FALSE(out.empty()) << o;
    EXPECT_TRUE(out.back().is_rapid());
    EXPECT_DOUBLE_EQ(out.back().end.z(), 5.0);
    EXPECT_EQ(r.moves[o].back().end, r.moves[o + 1].front().start) << o;
  }
  // Into the arc by a rapid of its own; into a line by the line itself.
  EXPECT_EQ(prepared.operations[1].moves.lead_in.size(), 1u);
  EXPECT_TRUE(r.moves[1][1].is_arc());
  EXPECT_TRUE(prepared.operations[2].moves.lead_in.empty());
  EXPECT_TRUE(prepared.operations[2].moves.first_start.has_value());
  // Within an operation the moves join up too.
  for (std::size_t o = 0; o < 3; ++o) {
    for (std::size_t i = 1; i < r.moves[o].size(); ++i) {
      EXPECT_LT((r.moves[o][i].start - r.moves[o][i - 1].end).norm(), 1e-9)
          << o << " line " << r.moves[o][i].line;
    }
  }
}

TEST(JobMoves, AProgramChangedAfterPreparingIsAnError) {
  const auto dir = scratch_dir("changed");
  Job job = job_on(dir);
  const PreparedJob prepared = prepare_job(job);
  std::ofstream(dir / "p.ngc", std::ios::app) << "G1 X5\n";  // after M2: not a move
  EXPECT_NO_THROW(replay(prepared));
  std::ofstream(dir / "p.ngc") << "G21 G90\nG0 Z5\nG1 X5 F100\n" << kProgram;
  try {
    replay(prepared);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, (dir / "p.ngc").string());
    EXPECT_NE(e.message().find("reads differently than when the job started"), std::string::npos)
        << e.message();
  }
}

}  // namespace
}  // namespace cwe
