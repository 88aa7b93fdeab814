#include "cwe/io/cl_writers.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <system_error>
#include <utility>

#include <fmt/compile.h>
#include <fmt/format.h>
#include <tbb/task_group.h>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/io/fixed_decimal.hpp"
#include "cwe/io/force_plot.hpp"

namespace cwe {
namespace {

double degrees(double radians) { return radians * 180.0 / kPi; }

// A number the rows print with a fixed count of decimals: "{}" of fixed(v, n) is "{:.nf}" of v,
// by write_fixed where it can (most of the rows' time went into fmt's exact rounding).
struct Fixed {
  double value;
  int decimals;
};
Fixed fixed(double value, int decimals) { return {value, decimals}; }

// A value that rounds to zero at `decimals` places, without its sign: "0.000", never "-0.000"
// (the sign of a rounding residue, such as the mean lateral force of a symmetric slot, says
// nothing and would differ between runs that agree).
double unsigned_zero(double value, int decimals) {
  // Half a unit of the last decimal, for the columns' 0 to 9 decimals (no pow per value).
  static constexpr double kHalfUnit[] = {0.5,  0.05, 5e-3, 5e-4, 5e-5,
                                         5e-6, 5e-7, 5e-8, 5e-9, 5e-10};
  const double half = kHalfUnit[std::clamp(decimals, 0, 9)];
  return std::abs(value) < half ? 0.0 : value;
}

}  // namespace
}  // namespace cwe

template <>
struct fmt::formatter<cwe::Fixed> {
  constexpr auto parse(fmt::format_parse_context& context) { return context.begin(); }
  template <class Context>
  auto format(const cwe::Fixed& f, Context& context) const {
    char text[cwe::kFixedDecimalMax];
    if (const char* end = cwe::write_fixed(text, f.value, f.decimals)) {
      return std::copy(static_cast<const char*>(text), end, context.out());
    }
    return fmt::format_to(context.out(), "{:.{}f}", f.value, f.decimals);
  }
};

namespace cwe {

OutputFolder::OutputFolder(const std::filesystem::path& out, const std::string& name)
    : target_(out / name),
      temporary_(out / (name + ".tmp-" + std::to_string(static_cast<long>(::getpid())))) {}

OutputFolder::~OutputFolder() {
  std::error_code ec;
  if (!committed_) std::filesystem::remove_all(temporary_, ec);
}

void OutputFolder::write(const std::string& name, std::string_view bytes) {
  write_file_atomically(temporary_ / name, bytes);
}

void OutputFolder::commit() {
  std::error_code ec;
  std::filesystem::create_directories(temporary_, ec);
  std::filesystem::remove_all(target_, ec);
  std::filesystem::rename(temporary_, target_, ec);
  if (ec) {
    throw InputError(SourceLocation{target_.string()},
                     "cannot write the output folder: " + ec.message());
  }
  committed_ = true;
}

const char* const kForcesCsvHeader =
    "cl,move,feed_per_tooth_mm,mean_fx_n,mean_fy_n,mean_fz_n,peak_fx_n,peak_fy_n,peak_fz_n,"
    "peak_resultant_n,mean_torque_nm,peak_torque_nm,mean_power_w,line,operation,feed_mm_min,"
    "spindle_rpm,max_chip_mm,mean_world_fx_n,mean_world_fy_n,mean_world_fz_n,peak_world_fx_n,"
    "peak_world_fy_n,peak_world_fz_n,tool\n";

ReportUnit ReportUnit::of(const std::string& units) {
  if (units != "in") return {};
  return {kMillimetresPerInch, 1, "in"};
}

std::string ReportUnit::header(std::string mm_header) const {
  for (std::size_t at = mm_header.find("mm"); at != std::string::npos;
       at = mm_header.find("mm", at + name.size())) {
    mm_header.replace(at, 2, name);
  }
  return mm_header;
}

std::string forces_csv_row(std::size_t k, const ClPoint& cl, std::size_t operation, int tool,
                           double feed_rate, const ClForces& f, const ReportUnit& unit) {
  const int e = unit.extra_decimals;
  const auto f3 = [](double value) { return fixed(value, 3); };
  const auto mean3 = [](double value) { return fixed(unsigned_zero(value, 3), 3); };
  return fmt::format(
      FMT_COMPILE("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n"),
      k, cl.move + 1, fixed(unit.length(f.feed_per_tooth), 6 + e), mean3(f.mean_force.x()),
      mean3(f.mean_force.y()), mean3(f.mean_force.z()), f3(f.peak_force.x()), f3(f.peak_force.y()),
      f3(f.peak_force.z()), f3(f.peak_resultant), fixed(unsigned_zero(f.mean_torque, 5), 5),
      fixed(f.peak_torque, 5), mean3(f.mean_power), cl.line, operation,
      fixed(unit.length(feed_rate), 3 + e), fixed(f.spindle_speed, 1),
      fixed(unit.length(f.max_chip), 6 + e), mean3(f.mean_force_world.x()),
      mean3(f.mean_force_world.y()), mean3(f.mean_force_world.z()), f3(f.peak_force_world.x()),
      f3(f.peak_force_world.y()), f3(f.peak_force_world.z()), tool);
}

// One engagement.jsonl line: the engaged discs and rings, angles in degrees, heights and radii in
// `unit`.
std::string engagement_jsonl_line(std::size_t k, const ClPoint& cl, const EngagementMap& map,
                                  const ReportUnit& unit) {
  const int e = unit.extra_decimals;
  std::string line;
  auto out = std::back_inserter(line);
  // The engaged bands of one kind (discs z0–z1, rings r0–r1) as a JSON array's items, each with
  // its intervals in degrees.
  const auto bands = [&](const auto& list, const char* lo, const char* hi, auto from, auto to) {
    bool first = true;
    for (const auto& band : list) {
      if (band.phi.empty()) continue;
      fmt::format_to(out, FMT_COMPILE(R"({}{{"{}":{},"{}":{},"intervals":[)"), first ? "" : ",", lo,
                     fixed(unit.length(band.*from), 4 + e), hi,
                     fixed(unit.length(band.*to), 4 + e));
      first = false;
      for (std::size_t i = 0; i < band.phi.size(); ++i) {
        fmt::format_to(out, FMT_COMPILE("{}[{},{}]"), i ? "," : "",
                       fixed(degrees(band.phi[i].lo), 3), fixed(degrees(band.phi[i].hi), 3));
      }
      line += "]}";
    }
  };
  fmt::format_to(out, FMT_COMPILE(R"({{"cl":{},"move":{},"discs":[)"), k, cl.move + 1);
  bands(map.discs, "z0", "z1", &DiscEngagement::z0, &DiscEngagement::z1);
  line += R"(],"bottom":{"rings":[)";
  bands(map.rings, "r0", "r1", &RingEngagement::r0, &RingEngagement::r1);
  line += "]}}\n";
  return line;
}

const char* const kEngagementCsvHeader =
    "cl,move,line,x,y,z,i,j,k,feed_x,feed_y,feed_z,engaged,phi_entry_deg,phi_exit_deg,"
    "axial_depth_mm,area_mm2,u,path_mm,motion,operation,tool\n";

// Lengths in `unit`.
std::string engagement_csv_row(std::size_t k, const ClPoint& cl, const ToolState& state,
                               const EngagementMap& map, std::size_t operation, int tool,
                               const ReportUnit& unit) {
  const int p = 4 + unit.extra_decimals;
  const Vec3 at = cl.position / unit.mm;
  const auto unit6 = [](double value) { return fixed(unsigned_zero(value, 6), 6); };
  const auto coordinate = [&](double value) { return fixed(unsigned_zero(value, p), p); };
  return fmt::format(
      FMT_COMPILE("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n"), k,
      cl.move + 1, cl.line, coordinate(at.x()), coordinate(at.y()), coordinate(at.z()),
      unit6(cl.axis.x()), unit6(cl.axis.y()), unit6(cl.axis.z()), unit6(cl.feed_direction.x()),
      unit6(cl.feed_direction.y()), unit6(cl.feed_direction.z()), map.engaged ? 1 : 0,
      fixed(degrees(map.phi_entry), 3), fixed(degrees(map.phi_exit), 3),
      fixed(unit.length(map.axial_depth), p), fixed(unit.area(map.area), p + unit.extra_decimals),
      fixed(cl.u, 6), fixed(unit.length(cl.path_length), p), to_string(state.motion), operation,
      tool);
}

EngagementFiles::EngagementFiles(const std::filesystem::path& folder, bool forces,
                                 const ReportUnit& unit)
    : unit_(unit), csv_(folder / "engagement.csv"), jsonl_(folder / "engagement.jsonl") {
  csv_.append(unit.header(kEngagementCsvHeader));
  if (forces) {
    forces_.emplace(folder / "forces.csv");
    forces_->append(unit.header(kForcesCsvHeader));
  }
}

void EngagementFiles::add(const ClResult& r) {
  csv_block_ += engagement_csv_row(r.index, r.cl, r.state, r.map, r.operation + 1, r.tool, unit_);
  jsonl_block_ += engagement_jsonl_line(r.index, r.cl, r.map, unit_);
  if (forces_ && r.forces != nullptr) {
    forces_block_ +=
        forces_csv_row(r.index, r.cl, r.operation + 1, r.tool, r.feed_rate, *r.forces, unit_);
  }
  flush(false);
}

void EngagementFiles::finish() { flush(true); }

std::vector<std::filesystem::path> EngagementFiles::commit() {
  csv_.commit();
  jsonl_.commit();
  std::vector<std::filesystem::path> made{csv_.path(), jsonl_.path()};
  if (forces_) {
    forces_->commit();
    made.push_back(forces_->path());
  }
  return made;
}

void EngagementFiles::flush(bool force) {
  if (!force && csv_block_.size() + jsonl_block_.size() + forces_block_.size() < (1u << 20)) {
    return;
  }
  csv_.append(csv_block_);
  jsonl_.append(jsonl_block_);
  if (forces_) forces_->append(forces_block_);
  csv_block_.clear();
  jsonl_block_.clear();
  forces_block_.clear();
}

// The figures' tasks have a context of their own (isolated). A task_group's default context
// binds, when its first task is run, to the context of the task running it: here a stage of the
// main loop's pipeline, which ends while the figures go on. A later pipeline's cancellation (an
// error in a move) then walked the dead context as an ancestor of this one and crashed.
struct Figures::Drawing {
  tbb::task_group_context context{tbb::task_group_context::isolated};
  tbb::task_group tasks{context};
};

Figures::Figures(const std::filesystem::path& folder, MapChoice maps, MapChoice curves, bool forces,
                 std::size_t cl_count)
    : maps_(std::move(maps)),
      curves_(std::move(curves)),
      map_folder_(folder, "maps"),
      path_stride_(std::max<std::size_t>(1, (cl_count + kPathPoints - 1) / kPathPoints)),
      drawing_(std::make_unique<Drawing>()) {
  if (forces) curve_folder_.emplace(folder, "force_curves");
}

Figures::~Figures() {
  // After commit() nothing is left to draw. Before it (an error elsewhere) the figures are never
  // written: those not yet started are dropped (their context is the figures' own, so an error's
  // cancellation of the main loop does not reach them), and their own errors no longer matter.
  try {
    drawing_->tasks.cancel();
    drawing_->tasks.wait();
  } catch (...) {  // NOLINT(bugprone-empty-catch)
  }
}

bool Figures::wants_curve(std::size_t index, bool engaged) {
  curve_ = curves_.chosen(index, engaged);
  return curve_;
}

void Figures::add(const ClResult& r) {
  const std::size_t k = r.index;
  const EngagementMap& map = r.map;
  if (k % path_stride_ == 0) {
    along_.push_back({static_cast<int>(k), map.engaged, degrees(map.phi_entry),
                      degrees(map.phi_exit), map.axial_depth});
  }
  const bool curve = r.forces != nullptr && curve_ && curve_folder_;
  curve_ = false;
  const bool chosen = maps_.chosen(k, map.engaged);
  if (!curve && !chosen) return;  // most CLs: no figure, nothing to name
  const std::string place =
      fmt::format("CL {} · move {} ({} line {})", k, r.cl.move + 1,
                  std::filesystem::path(r.file).filename().string(), r.cl.line);
  const std::string name = fmt::format("cl_{:06d}", k);
  // The figures are drawn from copies: the CL's data is gone once the sink returns.
  if (curve) {
    const ClForces& f = *r.forces;
    ForcePlotInfo info{fmt::format("{} · fz {:.4f} mm · {:.0f} rev/min", place, f.feed_per_tooth,
                                   f.spindle_speed)};
    drawing_->tasks.run([this, name, curve = f.curve, info = std::move(info)] {
      curve_folder_->write(name + ".csv", force_curve_csv(curve));
      curve_folder_->write(name + ".png", force_curve_png(curve, info));
      curve_folder_->write(name + ".svg", force_curve_svg(curve, info));
    });
    ++curves_written_;
  }
  if (!chosen) return;
  MapPlotInfo info{fmt::format("{} · {}", place, r.cutter.name()), 0.5 * r.cutter.diameter(),
                   r.cutter.flute_length()};
  drawing_->tasks.run([this, name, map, info = std::move(info)] {
    map_folder_.write(name + ".png", engagement_map_png(map, info));
    map_folder_.write(name + ".svg", engagement_map_svg(map, info));
  });
  ++maps_written_;
}

void Figures::finish(const std::string& title) {
  drawing_->tasks.wait();
  map_folder_.write("path.png", engagement_path_png(along_, title));
  map_folder_.write("path.svg", engagement_path_svg(along_, title));
}

std::vector<std::filesystem::path> Figures::commit() {
  drawing_->tasks.wait();
  map_folder_.commit();
  std::vector<std::filesystem::path> made{map_folder_.path()};
  if (curve_folder_) {
    curve_folder_->commit();
    made.push_back(curve_folder_->path());
  }
  return made;
}

}  // namespace cwe
