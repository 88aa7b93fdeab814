// The per-CL rows of engagement.csv and forces.csv.
#include "cwe/io/cl_writers.hpp"

#include <gtest/gtest.h>

#include <string>

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

}  // namespace
}  // namespace cwe
