#pragma once
// A drawing of a cutter's profile as a standalone SVG document: the silhouette (both sides of the
// axis) coloured by patch kind, the shank outline dashed, the axis, the tip, and the key
// dimensions. Millimetres in the labels; the drawing is scaled to fit.

#include <string>

#include "cwe/tool/cutter.hpp"

namespace cwe {

std::string profile_svg(const Cutter& cutter);

}  // namespace cwe
