#pragma once
// Colours and text escaping shared by the SVG drawings (private to io).

#include <string>

#include "cwe/tool/cutter.hpp"

namespace cwe::io_detail {

inline const char* patch_color(PatchKind kind) {
  switch (kind) {
    case PatchKind::kFlatBottom:
      return "#d62728";
    case PatchKind::kStep:
      return "#9467bd";
    case PatchKind::kCylinder:
      return "#1f77b4";
    case PatchKind::kCone:
      return "#2ca02c";
    case PatchKind::kSphere:
      return "#ff7f0e";
    case PatchKind::kTorus:
      return "#e377c2";
  }
  return "#000000";
}

inline std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace cwe::io_detail
