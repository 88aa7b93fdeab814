#pragma once
// APT CLDATA (source form, as CAM systems write it) to moves.
//
// Records: PARTNO, UNITS/MM|INCHES, CUTTER/ (1 to 7 values, see cwe/tool/apt.hpp), LOADTL/n,
// TLAXIS/i,j,k, MULTAX[/ON|OFF], FROM/, GOTO/x,y,z[,i,j,k], GODLTA/, RAPID, FEDRAT/f[,MMPM|IPM],
// SPINDL/, CIRCLE/xc,yc,zc,i,j,k,r[,…] followed by the GOTO that ends the arc, `$` continuation
// lines, `$$` comments, FINI. Unknown major words become warnings in Toolpath::warnings (one per
// record, with its line); malformed records are InputErrors with file and line. See
// docs/cldata.md.

#include <string>
#include <string_view>

#include "cwe/geometry/vec.hpp"
#include "cwe/toolpath/toolpath.hpp"

namespace cwe {

// `start`: where the tool tip is before the first motion when the program has no FROM. A program
// that states no axis before its first GOTO (no FROM or TLAXIS with one) starts in that GOTO's
// orientation, +Z for a 3-axis GOTO.
Toolpath read_cldata(std::string_view text, const std::string& source,
                     const Vec3& start = Vec3::Zero());
Toolpath read_cldata_file(const std::string& path, const Vec3& start = Vec3::Zero());

}  // namespace cwe
