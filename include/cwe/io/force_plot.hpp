#pragma once
// The cutting force over one spindle revolution (ForceModel's ClForces::curve) as a figure (PNG
// or SVG) and as CSV text, in the style of the force plots of the milling literature (Altintas,
// Manufacturing Automation, ch. 2): the force components against the spindle angle.
//
// Like the engagement plots, each figure is drawn once by a single cairo routine onto either an
// image surface (PNG) or an SVG surface, so both outputs show the same picture; the functions
// return the file's bytes (or text) and never write files or print.
//
// Errors: cwe::InputError for an empty curve (figures only) and for a NaN or infinite angle,
// force component or torque, or a force too large for its magnitude to be a finite number.
// Cairo failures (out of memory) throw std::runtime_error.

#include <string>
#include <vector>

#include "cwe/process/force_model.hpp"

namespace cwe {

struct ForcePlotInfo {
  std::string title;  // e.g. "CL 120 · move 14 (line 37) · fz 0.05 mm"
};

// The curve as a figure of plot_layout::kForceWidth × kForceHeight pixels.
//
// Spindle angle θ in degrees 0…360 across (ticks every 45°). The curve is periodic: a sample is
// drawn at its angle modulo 360°, samples are joined in order of that angle, and the line runs
// on through 0° and 360° to the samples on the other side, so a revolution sampled at
// k·Δ, k = 0…n−1, is closed from 360° − Δ to 360°.
// Left axis, force in N, tool frame (x along the feed, z the axis): F_x, F_y, F_z and the
// resultant |F| as four solid lines of the colours below, with a legend above the plot. Right
// axis, torque about the tool axis in N·m: a dashed line. Both axes start at 0 when no force
// component and no torque is negative, and are otherwise symmetric about 0 (so their zeros
// coincide); each ends at the first multiple of its tick step (a 1-2-2.5-5 step giving about 5
// ticks, 4 each side of 0 when symmetric) at least 2% above the largest magnitude it shows, so
// that peaks stay clear of the frame; an axis with nothing but zeros runs to 1. A curve of zeros
// (no cutting) draws flat lines at 0 and the note "no cutting force". The SVG has one vertex per
// sample and line, so curves of up to some 10⁴ samples stay below a few MB.
//
// The SVG carries `title` as its <title> and the legend ("Fx (N)", "Fy (N)", "Fz (N)",
// "|F| (N)", "torque (N·m)") in its <desc>: cairo writes the figure's words as glyph outlines.
std::string force_curve_png(const std::vector<ForceSample>& curve, const ForcePlotInfo& info);
std::string force_curve_svg(const std::vector<ForceSample>& curve, const ForcePlotInfo& info);

// The curve as CSV: the header
//     angle_deg,fx_n,fy_n,fz_n,resultant_n,torque_nm
// then one row per sample, in the curve's order: the spindle angle in degrees as given (not
// wrapped), 4 decimals; the force components in the tool frame and |F| in N, 4 decimals; the
// torque in N·m, 6 decimals. Fixed notation, '.' as the decimal point, "\n" line ends. An empty
// curve gives the header alone.
std::string force_curve_csv(const std::vector<ForceSample>& curve);

// The force figure's geometry in pixels (SVG user units are the same), for callers that place
// things on it and for tests that look at pixels. y grows downwards.
namespace plot_layout {

inline constexpr int kForceWidth = 1000;
inline constexpr int kForceHeight = 560;
// Plot area: θ = 0° at kForceLeft, 360° at kForceLeft + kForcePlotWidth (2 px per degree); the
// force and torque axes' tops at kForceTop, their bottoms (0, or minus the top when symmetric)
// at kForceTop + kForcePlotHeight.
inline constexpr double kForceLeft = 100;
inline constexpr double kForceTop = 80;
inline constexpr double kForcePlotWidth = 720;
inline constexpr double kForcePlotHeight = 400;

// Line colours, 0xRRGGBB.
inline constexpr unsigned kForceXColor = 0x1f77b4;
inline constexpr unsigned kForceYColor = 0xff7f0e;
inline constexpr unsigned kForceZColor = 0x2ca02c;
inline constexpr unsigned kResultantColor = 0xd62728;
inline constexpr unsigned kTorqueColor = 0x9467bd;

// The axes' ranges, [bottom, top] in N and N·m, as force_curve_png draws them. Throws
// InputError like force_curve_png.
struct ForceAxes {
  double force_bottom = 0, force_top = 1, force_step = 0.2;
  double torque_bottom = 0, torque_top = 1, torque_step = 0.2;
};
ForceAxes force_axes(const std::vector<ForceSample>& curve);

}  // namespace plot_layout

}  // namespace cwe
