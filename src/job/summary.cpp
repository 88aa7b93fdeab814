#include "cwe/job/summary.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "cwe/engagement/dexel_engagement.hpp"

namespace cwe {
namespace {

double degrees(double radians) { return radians * 180.0 / kPi; }

nlohmann::json operations_json(const PreparedJob& job, const JobResult& run) {
  nlohmann::json ops = nlohmann::json::array();
  for (std::size_t o = 0; o < job.operations.size(); ++o) {
    const PreparedOperation& op = job.operations[o];
    ops.push_back({{"tool", op.cutter.name()},
                   {"tool_number", op.tool},
                   {"path", op.path},
                   {"moves", run.per_operation[o].moves},
                   {"cl_points", op.cl_points},
                   {"cl_step_mm", op.sampling.step}});
    if (op.forces) {
      ops.back()["coefficients"] = op.forces->coefficients().name;
      ops.back()["flutes"] = op.forces->flutes();
      ops.back()["helix_deg"] = degrees(op.forces->helix_angle());
    }
  }
  return ops;
}

nlohmann::json engagement_json(const PreparedJob& job, const JobResult& run,
                               const JobSummary& extras) {
  EngagementOptions engagement;
  engagement.contact = job.simulation.effective_tolerance();  // as simulate_engagement takes it
  const DexelEngagement grid(job.operations.front().cutter, job.simulation.resolution, engagement);
  return {{"cl_points", run.cl_points},
          {"engaged_cl_points", run.engaged_cl_points},
          {"disc_height_mm", grid.disc_height()},
          {"phi_step_deg", degrees(grid.phi_step())},
          {"contact_mm", grid.contact()},
          {"max_axial_depth_mm", run.deepest},
          {"max_area_mm2", run.largest_area},
          {"maps", extras.maps},
          {"files", {"engagement.csv", "engagement.jsonl", "maps/"}}};
}

nlohmann::json forces_json(const PreparedJob& job, const JobResult& run, const JobSummary& extras) {
  const auto extreme = [](const ForceExtremes::Extreme& e) {
    return nlohmann::json{{"value", e.value}, {"cl", e.cl}, {"file", e.file}, {"line", e.line}};
  };
  const ForceModel& model = *job.operations.front().forces;
  const ForceExtremes& extremes = run.extremes;
  return {{"coefficients", coefficient_names(job)},
          {"coefficients_source", coefficient_names(job, true)},
          {"angle_step_deg", 360.0 / model.samples()},
          {"runout_mm", job.forces->model.runout.offset},
          {"runout_angle_deg", degrees(job.forces->model.runout.angle)},
          {"spindle_rpm", job.forces->spindle ? nlohmann::json(*job.forces->spindle)
                                              : nlohmann::json("from the program")},
          {"cutting_cl_points", extremes.cutting},
          {"max_peak_resultant_n", extreme(extremes.force)},
          {"max_peak_torque_nm", extreme(extremes.torque)},
          {"max_mean_power_w", extreme(extremes.power)},
          {"max_chip_mm", extreme(extremes.chip)},
          {"curves", extras.curves},
          {"files", {"forces.csv", "force_curves/"}}};
}

// The rapid moves that cut (the first kRapidCutsListed) and the programs' warnings.
void add_rapid_cuts_and_warnings(const PreparedJob& job, const RemovalSummary& removal,
                                 nlohmann::json& summary) {
  nlohmann::json rapids = nlohmann::json::array();
  for (std::size_t i = 0; i < removal.rapid_cuts.size() && i < kRapidCutsListed; ++i) {
    const RapidCut& cut = removal.rapid_cuts[i];
    rapids.push_back({{"move", cut.move + 1},
                      {"file", cut.location.source},
                      {"line", cut.location.line},
                      {"removed_mm3", cut.volume}});
  }
  summary["rapid_cuts"] = {{"count", removal.rapid_cut_count}, {"first", rapids}};
  nlohmann::json warnings = nlohmann::json::array();
  for (const PreparedOperation& op : job.operations) {
    for (const Diagnostic& d : op.toolpath.warnings) {
      warnings.push_back(
          {{"file", d.location.source}, {"line", d.location.line}, {"message", d.message}});
    }
  }
  summary["toolpath_warnings"] = warnings;
  nlohmann::json job_warnings = nlohmann::json::array();
  for (const Diagnostic& d : job.warnings) {
    job_warnings.push_back(
        {{"setting", d.location.source}, {"line", d.location.line}, {"message", d.message}});
  }
  summary["warnings"] = job_warnings;
}

}  // namespace

std::string job_paths(const PreparedJob& job) {
  std::vector<std::string> paths;
  for (const PreparedOperation& op : job.operations) paths.push_back(op.path);
  return fmt::format("{}", fmt::join(paths, ", "));
}

std::string job_summary(const PreparedJob& job, const JobResult& run, const JobSummary& extras) {
  const SimulationOptions& simulation = job.simulation;
  const RemovalSummary& removal = run.removal;
  const TriDexel::Volume& initial = run.initial_volume;
  const TriDexel::Volume& final_volume = run.final_volume;
  std::vector<std::string> tool_names;
  for (const PreparedOperation& op : job.operations) {
    tool_names.push_back(op.cutter.name());
  }
  nlohmann::json summary;  // keys sorted: the order of assignment does not show
  summary["resolution_mm"] = simulation.resolution;
  summary["moves"] = removal.moves;
  summary["initial_volume_mm3"] = initial.mean();
  summary["final_volume_mm3"] = final_volume.mean();
  summary["removed_volume_mm3"] = initial.mean() - final_volume.mean();
  if (run.stock) {
    const TriDexel::Memory memory = run.stock->memory();
    summary["workpiece"] = "dexel";
    summary["rays"] = run.stock->ray_count();
    summary["peak_memory_bytes"] = memory.peak();
    summary["final_volume_by_family_mm3"] = final_volume.by_family;
    summary["volume_spread_mm3"] = final_volume.spread();
    summary["bytes_per_ray"] =
        static_cast<double>(memory.total()) / static_cast<double>(run.stock->ray_count());
  } else if (run.brep) {
    summary["workpiece"] = "brep";
    summary["stock_solid"] = {{"file", "stock.step"},
                              {"faces", run.brep->faces()},
                              {"volume_mm3", run.brep->volume()},
                              {"moves_lofted", run.brep->moves_lofted()},
                              {"worst_loft_deviation_mm", run.brep->worst_loft_deviation()},
                              {"moves_in_linear_pieces", run.brep->moves_in_lines()},
                              {"removal_volumes_off", run.brep->removal_volumes_off()},
                              {"removal_volumes_replaced", run.brep->removal_volumes_replaced()},
                              {"cuts_from_mended_stock", run.brep->cuts_from_mended_stock()},
                              {"worst_removal_volume_relative", run.brep->worst_removal_volume()}};
  } else {
    summary["workpiece"] = "mesh";
    summary["facet_mm"] = job.facet;
    summary["triangles"] = run.mesh->triangles();
  }
  summary["seconds"] = extras.set_up_seconds + extras.simulation_seconds + extras.closing_seconds;
  summary["seconds_by_stage"] = {{"set_up", extras.set_up_seconds},
                                 {"simulation", extras.simulation_seconds},
                                 {"closing", extras.closing_seconds}};
  summary["tool"] = fmt::format("{}", fmt::join(tool_names, ", "));
  summary["path"] = job_paths(job);
  summary["stock"] = extras.stock;
  if (job.stock.step) {
    const StepModel& step = *job.stock.step;
    summary["stock_step"] = {
        {"solids", step.solids()},
        {"file_unit", step.file_unit()},
        {"volume_mm3", step.volume()},
        {"tessellation_mm", step_tessellation(simulation, job.workpiece == WorkpieceKind::kMesh)}};
  }
  if (job.stock.mesh_solid) {
    summary["stock_mesh_solid"] = {{"triangles", job.stock.mesh->triangles.size()},
                                   {"solids", job.stock.mesh_solid->solids()},
                                   {"volume_mm3", job.stock.mesh_solid->volume()}};
  }
  summary["report_units"] = extras.report_units;
  summary["threads"] = job.threads;
  summary["operations"] = operations_json(job, run);
  summary["feed_moves"] = removal.feed_moves;
  summary["rapid_moves"] = removal.rapid_moves;
  summary["cutting_moves"] = removal.cutting_moves;
  summary["linear_sweeps"] = removal.linear_pieces;
  summary["tolerance_mm"] = simulation.effective_tolerance();
  summary["deviation_bound_mm"] = removal.deviation_bound;
  if (extras.mesh != nullptr) {
    summary["stock_mesh"] = {{"file", "stock.stl"},
                             {"triangles", extras.mesh->triangles.size()},
                             {"volume_mm3", extras.mesh->volume()}};
    if (run.stock) {  // contoured from the rays
      summary["stock_mesh"]["stride"] = extras.mesh_stride;
      summary["stock_mesh"]["lattice_mm"] = extras.mesh_stride * simulation.resolution;
    }
    if (run.brep) summary["stock_mesh"]["deviation_mm"] = step_tessellation(simulation, false);
    if (extras.ply) summary["stock_mesh"]["ply"] = "stock.ply";
    if (extras.off) summary["stock_mesh"]["off"] = "stock.off";
  }
  if (extras.engagement) summary["engagement"] = engagement_json(job, run, extras);
  if (job.forces) summary["forces"] = forces_json(job, run, extras);
  add_rapid_cuts_and_warnings(job, removal, summary);
  return summary.dump(2) + "\n";
}

}  // namespace cwe
