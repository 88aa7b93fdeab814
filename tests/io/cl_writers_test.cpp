// The per-CL rows of engagement.csv and forces.csv.
#include "cwe/io/cl_writers.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

#include "cwe/tool/tool_spec.hpp"

namespace cwe {
namespace {

// A value that rounds to zero prints as zero without a sign (the sign of a rounding residue says
// nothing and differs between runs that agree); a value that rounds to something keeps its sign.
TEST(ClWriters, ValuesThatRoundToZeroPrintWithoutASign) {
  ClPoint cl;
  cl.position = Vec3(-0.00001, 12.5, -3.0);
  cl.axis = Vec3(-1e-12, 0.0, 1.0);
  cl.feed_direction = Vec3(1.0, -1e-9, -0.0000006);
  ClForces f;
  f.mean_force = Vec3(-1e-9, -0.0004999, -0.0006);
  f.mean_force_world = Vec3(-1e-13, 2.5, -0.0);
  f.mean_torque = -4e-6;
  f.mean_power = -1e-7;
  const std::string forces = forces_csv_row(0, cl, 0, 1, 1000.0, f);
  EXPECT_EQ(forces.find("-0.000,"), std::string::npos) << forces;
  EXPECT_NE(forces.find(",0.000,0.000,-0.001,"), std::string::npos) << forces;  // mean F
  EXPECT_NE(forces.find(",0.000,2.500,0.000,"), std::string::npos) << forces;   // world
  EXPECT_NE(forces.find(",0.00000,"), std::string::npos) << forces;             // torque

  const ToolState state = tool_state(cl, Vec3::UnitX());
  const std::string row =
      engagement_csv_row(0, cl, state, EngagementMap{}, 0, 1, ReportUnit::of("mm"));
  EXPECT_EQ(row.find("-0.0000,"), std::string::npos) << row;
  EXPECT_NE(row.find(",0.0000,12.5000,-3.0000,0.000000,0.000000,1.000000,"), std::string::npos)
      << row;
  EXPECT_NE(row.find(",1.000000,0.000000,-0.000001,"), std::string::npos) << row;
}

// Runs `f` below 4 KiB × (depth + 1) of the stack written over: a pipeline run there has its
// context far from an earlier one's at the caller's depth, whose memory now reads as garbage
// (what a long job does between two batches).
__attribute__((noinline)) void below_used_stack(int depth, const std::function<void()>& f) {
  volatile char junk[4096];
  for (volatile char& c : junk) c = static_cast<char>(0xAB);
  if (depth > 0) {
    below_used_stack(depth - 1, f);
  } else {
    f();
  }
  junk[0] = 1;
}

// The main loop hands CLs to Figures in a stage of a pipeline (one per batch of moves); the
// figures are drawn on after that pipeline ends. A later batch's pipeline that fails (a move
// OpenCASCADE cannot cut, with engagement run in nested loops) must stop with its error, not
// crash: the figures' tasks were bound to the first pipeline's context and its cancellation
// walked the dead context (a B-rep run of the CATIA program died so at its last move).
TEST(Figures, OutliveThePipelineThatHandedThemTheirMaps) {
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / "cwe-figures-pipelines";
  fs::remove_all(out);
  fs::create_directories(out);
  const Cutter cutter = cutter_from_spec("flat:10,30");
  ClPoint cl;
  cl.position = Vec3(0.0, 0.0, 0.0);
  cl.axis = Vec3::UnitZ();
  cl.feed_direction = Vec3::UnitX();
  const ToolState state = tool_state(cl, Vec3::UnitX());
  EngagementMap map;
  map.discs.push_back({0.0, 1.0, 0, {{0.0, 1.0}}});
  map.engaged = true;
  const Move move;
  const std::string file = "program.ngc";
  constexpr std::size_t kCls = 6;
  {
    Figures figures(out, MapChoice{1, {}, false, false}, MapChoice{}, false, kCls);
    std::size_t next = 0;
    tbb::parallel_pipeline(
        2, tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                               [&](tbb::flow_control& control) {
                                                 if (next == kCls) control.stop();
                                                 return next++;
                                               }) &
               tbb::make_filter<std::size_t, void>(
                   tbb::filter_mode::serial_in_order, [&](std::size_t k) {
                     figures.add({k, cl, state, map, cutter, 0, 1, file, move});
                   }));
    int batches = 0;
    const auto failing_batch = [&] {
      tbb::parallel_pipeline(
          2, tbb::make_filter<void, int>(tbb::filter_mode::serial_in_order,
                                         [&](tbb::flow_control&) {
                                           if (++batches == 3) {
                                             throw std::runtime_error("a move failed");
                                           }
                                           return batches;
                                         }) &
                 tbb::make_filter<int, void>(tbb::filter_mode::parallel, [](int) {
                   tbb::parallel_for(0, 4, [](int) {});
                 }));
    };
    EXPECT_THROW(below_used_stack(4, failing_batch), std::runtime_error);
    figures.finish("path");
    figures.commit();
    EXPECT_EQ(figures.maps_written(), kCls);
  }
  for (std::size_t k = 0; k < kCls; ++k) {
    const std::string name = fmt::format("cl_{:06d}", k);
    EXPECT_TRUE(fs::exists(out / "maps" / (name + ".png"))) << name;
    EXPECT_TRUE(fs::exists(out / "maps" / (name + ".svg"))) << name;
  }
  fs::remove_all(out);
}

}  // namespace
}  // namespace cwe
