#pragma once
// Solids for the STEP tests (built with OpenCASCADE, written with cwe's own STEP writer).

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <gp_Ax2.hxx>

#include <filesystem>
#include <fstream>
#include <string>

#include "cwe/core/numbers.hpp"
#include "cwe/io/step_shape.hpp"

namespace cwe::test {

// A 60 × 40 × 20 mm block at the origin with two through holes of radius 5 along Z, at
// (15, 20) and (45, 20).
inline TopoDS_Shape block_with_holes() {
  TopoDS_Shape block = BRepPrimAPI_MakeBox(60.0, 40.0, 20.0).Shape();
  for (const double x : {15.0, 45.0}) {
    const TopoDS_Shape hole =
        BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, 20.0, -1.0), gp::DZ()), 5.0, 22.0).Shape();
    block = BRepAlgoAPI_Cut(block, hole).Shape();
  }
  return block;
}
inline constexpr double kBlockWithHolesVolume = 60.0 * 40.0 * 20.0 - 2.0 * kPi * 25.0 * 20.0;
// Its surface: the block's faces less the holes' discs, plus the holes' walls.
inline constexpr double kBlockWithHolesArea = 2.0 * (60.0 * 40.0 + 60.0 * 20.0 + 40.0 * 20.0) -
                                              4.0 * kPi * 25.0 + 2.0 * kTwoPi * 5.0 * 20.0;

inline void write_step_file(const TopoDS_Shape& shape, const std::filesystem::path& path) {
  std::ofstream(path, std::ios::binary) << step_bytes(shape);
}

}  // namespace cwe::test
