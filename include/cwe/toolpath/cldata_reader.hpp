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

#include "cwe/toolpath/toolpath.hpp"

namespace cwe {

Toolpath read_cldata(std::string_view text, const std::string& source);
Toolpath read_cldata_file(const std::string& path);

}  // namespace cwe
