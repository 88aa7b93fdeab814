#include "simulate_command.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/io/atomic_file.hpp"
#include "cwe/io/cl_sink.hpp"
#include "cwe/io/mesh_io.hpp"
#include "cwe/job/run.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"
#include "cwe/workpiece/dexel/dexel_mesh.hpp"
#include "cwe/io/cl_writers.hpp"
#include "job_file.hpp"

namespace cwe::app {
namespace {

// Rapid moves listed by line in the report (all are counted).
constexpr std::size_t kRapidCutsListed = 10;

MapChoice parse_maps(const std::string& text, std::size_t cl_count, const char* option = "--maps") {
  const SourceLocation where{option};
  MapChoice choice;
  if (text.empty() && std::string_view(option) == "--maps") {
    choice.every = std::max<std::size_t>(1, (cl_count + 9) / 10);
    choice.engaged_only = true;
    return choice;
  }
  if (text == "none" || text.empty()) return choice;
  const auto number = [&](std::string_view word) {
    std::size_t value = 0;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (word.empty() || ec != std::errc() || end != word.data() + word.size()) {
      throw InputError(where, fmt::format("'{}' in '{}' is not a whole number; expected every:N, "
                                          "cl:i,j,… or none",
                                          word, text));
    }
    return value;
  };
  const std::string_view view(text);
  if (view.starts_with("every:")) {
    choice.every = number(view.substr(6));
    if (choice.every == 0) throw InputError(where, "every:0: expected a period of at least 1");
    return choice;
  }
  if (view.starts_with("cl:")) {
    std::string_view rest = view.substr(3);
    while (true) {
      const std::size_t comma = rest.find(',');
      choice.cl.push_back(number(rest.substr(0, comma)));
      if (comma == std::string_view::npos) break;
      rest = rest.substr(comma + 1);
    }
    std::sort(choice.cl.begin(), choice.cl.end());
    return choice;
  }
  throw InputError(where, fmt::format("'{}': expected every:N, cl:i,j,… or none", text));
}

double degrees(double radians) { return radians * 180.0 / kPi; }

}  // namespace

void add_simulate_command(CLI::App& app, SimulateCommandOptions& options) {
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "The main job: run toolpaths through a stock (tri-dexel workpiece), extract the "
      "cutter-workpiece engagement at every cutter location and write engagement.csv, "
      "engagement.jsonl, maps/, the machined stock (stock.stl) and summary.json; with --forces "
      "also forces.csv. Options may come from a JSON job file (docs/simulate.md).");
  add_job_options(cmd, options);
  cmd->add_option("--out", options.out, "Output folder");
  cmd->add_option("--mesh-stride", options.mesh_stride,
                  "Contour stock.stl on every k-th ray position (lattice k·s); default: the "
                  "smallest k giving at most about 1,000,000 triangles")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--ply", options.ply,
                "Also write the stock as stock.ply (ASCII, double precision)");
  cmd->add_option("--maps", options.maps,
                  "Engagement-map figures: every:N, cl:i,j,… (CL indices from 0) or none "
                  "(default: the first engaged CL of each tenth of the path)");
  cmd->add_option("--force-curves", options.force_curves,
                  "Force-versus-angle curves (CSV and plots) in force_curves/: every:N, "
                  "cl:i,j,… or none (default none)");
  cmd->add_flag("--stock-only", options.stock_only,
                "Material removal only: no engagement outputs (faster)");
}

int run_simulate_command(SimulateCommandOptions options, std::ostream& out,
                         std::ostream* progress) {
  const auto started = std::chrono::steady_clock::now();
  read_job(options);
  require(options.out, "output folder", "--out");
  check_units(options.report_units, "--report-units");
  PreparedJob job = prepare_job(options, !options.stock_only);
  const SimulationOptions& simulation = job.simulation;
  const int threads = job.threads;
  const tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                        static_cast<std::size_t>(threads));
  std::vector<PreparedOperation>& operations = job.operations;
  const std::size_t cl_count = job.cl_count;
  if (options.stock_only && job.forces) {
    throw InputError(SourceLocation{"--forces"},
                     "forces need the engagement, which --stock-only skips; drop one of them");
  }
  MapChoice maps = parse_maps(options.stock_only ? "none" : options.maps, cl_count);
  if (!job.forces && !options.force_curves.empty() && options.force_curves != "none") {
    throw InputError(SourceLocation{"--force-curves"}, "force curves need --forces");
  }
  MapChoice curves =
      parse_maps(job.forces ? options.force_curves : "none", cl_count, "--force-curves");
  const StockSpec stock_spec = parse_stock_spec(options.stock, SourceLocation{"--stock"});
  TriDexel initial_stock = make_stock(stock_spec, simulation);  // before any output is opened
  const ReportUnit unit = ReportUnit::of(options.report_units);
  const std::filesystem::path folder(options.out);

  ProgressBar bar(options.quiet ? nullptr : progress);
  std::optional<EngagementFiles> files;
  std::optional<Figures> figures;
  std::vector<ClSink*> sinks;
  if (!options.stock_only) {
    files.emplace(folder, job.forces.has_value(), unit);
    figures.emplace(folder, maps, curves, job.forces.has_value());
    sinks = {&*files, &*figures};
  }
  JobResult run = run_job(job, std::move(initial_stock), RunOptions{!options.stock_only}, sinks,
                          [&](std::size_t done, std::size_t total) { bar(done, total); });
  if (!options.stock_only) {
    files->finish();
    const std::string title =
        operations.size() == 1
            ? fmt::format("Engagement along {} with {}",
                          std::filesystem::path(operations[0].path).filename().string(),
                          operations[0].cutter.name())
            : fmt::format("Engagement along {} operations", operations.size());
    figures->finish(title);
  }
  TriDexel& stock = run.stock;
  const TriDexel::Volume& initial = run.initial_volume;
  const RemovalSummary& removal = run.removal;
  const std::vector<RemovalSummary>& per_operation = run.per_operation;
  const ForceExtremes& extremes = run.extremes;
  const std::size_t engaged_cls = run.engaged_cl_points;
  const double deepest = run.deepest, largest_area = run.largest_area;
  const std::size_t maps_written = figures ? figures->maps_written() : 0;
  const std::size_t curves_written = figures ? figures->curves_written() : 0;
  const std::size_t cl_points = run.cl_points;
  const TriDexel::Volume& final_volume = run.final_volume;
  const TriDexel::Memory memory = stock.memory();
  const int stride =
      options.mesh_stride > 0 ? options.mesh_stride : dexel_mesh_stride(stock, kStockMeshTriangles);
  const TriangleMesh mesh = dexel_mesh(stock, stride);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  std::vector<std::string> tool_names, paths;
  for (const PreparedOperation& op : operations) {
    tool_names.push_back(op.cutter.name());
    paths.push_back(op.path);
  }
  nlohmann::json summary;
  summary["resolution_mm"] = simulation.resolution;
  summary["moves"] = removal.moves;
  summary["initial_volume_mm3"] = initial.mean();
  summary["final_volume_mm3"] = final_volume.mean();
  summary["removed_volume_mm3"] = initial.mean() - final_volume.mean();
  summary["rays"] = stock.ray_count();
  summary["peak_memory_bytes"] = memory.peak();
  summary["seconds"] = seconds;
  summary["tool"] = fmt::format("{}", fmt::join(tool_names, ", "));
  summary["path"] = fmt::format("{}", fmt::join(paths, ", "));
  summary["stock"] = options.stock;
  summary["report_units"] = unit.name;
  summary["threads"] = threads;
  nlohmann::json ops = nlohmann::json::array();
  for (std::size_t o = 0; o < operations.size(); ++o) {
    ops.push_back({{"tool", operations[o].cutter.name()},
                   {"tool_number", operations[o].tool},
                   {"path", operations[o].path},
                   {"moves", per_operation[o].moves},
                   {"cl_points", operations[o].cl_points},
                   {"cl_step_mm", operations[o].sampling.step}});
    if (operations[o].forces) {
      ops.back()["coefficients"] = operations[o].forces->coefficients().name;
      ops.back()["flutes"] = operations[o].forces->flutes();
      ops.back()["helix_deg"] = degrees(operations[o].forces->helix_angle());
    }
  }
  summary["operations"] = ops;
  summary["feed_moves"] = removal.feed_moves;
  summary["rapid_moves"] = removal.rapid_moves;
  summary["cutting_moves"] = removal.cutting_moves;
  summary["linear_sweeps"] = removal.linear_pieces;
  summary["tolerance_mm"] = simulation.effective_tolerance();
  summary["deviation_bound_mm"] = removal.deviation_bound;
  summary["final_volume_by_family_mm3"] = final_volume.by_family;
  summary["volume_spread_mm3"] = final_volume.spread();
  summary["bytes_per_ray"] =
      static_cast<double>(memory.total()) / static_cast<double>(stock.ray_count());
  summary["stock_mesh"] = {{"file", "stock.stl"},
                           {"stride", stride},
                           {"lattice_mm", stride * simulation.resolution},
                           {"triangles", mesh.triangles.size()},
                           {"volume_mm3", mesh.volume()}};
  if (options.ply) summary["stock_mesh"]["ply"] = "stock.ply";
  if (!options.stock_only) {
    EngagementOptions engagement;
    engagement.contact = simulation.effective_tolerance();  // as simulate_engagement takes it
    const DexelEngagement grid(operations.front().cutter, simulation.resolution, engagement);
    summary["engagement"] = {{"cl_points", cl_points},
                             {"engaged_cl_points", engaged_cls},
                             {"disc_height_mm", grid.disc_height()},
                             {"phi_step_deg", degrees(grid.phi_step())},
                             {"contact_mm", grid.contact()},
                             {"max_axial_depth_mm", deepest},
                             {"max_area_mm2", largest_area},
                             {"maps", maps_written},
                             {"files", {"engagement.csv", "engagement.jsonl", "maps/"}}};
  }
  if (job.forces) {
    const auto extreme = [](const ForceExtremes::Extreme& e) {
      return nlohmann::json{{"value", e.value}, {"cl", e.cl}, {"file", e.file}, {"line", e.line}};
    };
    const ForceModel& model = *operations.front().forces;
    summary["forces"] = {{"coefficients", coefficient_names(job)},
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
                         {"curves", curves_written},
                         {"files", {"forces.csv", "force_curves/"}}};
  }
  nlohmann::json rapids = nlohmann::json::array();
  for (std::size_t i = 0; i < removal.rapid_cuts.size() && i < kRapidCutsListed; ++i) {
    const RapidCut& cut = removal.rapid_cuts[i];
    rapids.push_back({{"move", cut.move + 1},
                      {"file", cut.location.source},
                      {"line", cut.location.line},
                      {"removed_mm3", cut.volume}});
  }
  summary["rapid_cuts"] = {{"count", removal.rapid_cuts.size()}, {"first", rapids}};
  nlohmann::json warnings = nlohmann::json::array();
  std::size_t warning_count = 0;
  for (const PreparedOperation& op : operations) {
    for (const Diagnostic& d : op.read.toolpath.warnings) {
      warnings.push_back(
          {{"file", d.location.source}, {"line", d.location.line}, {"message", d.message}});
      ++warning_count;
    }
  }
  summary["toolpath_warnings"] = warnings;

  // Everything is computed: commit the outputs, each whole; the summary last.
  if (files) files->commit();
  if (figures) figures->commit();
  const std::string title =
      fmt::format("cwe in-process stock after {}", summary["path"].get<std::string>());
  write_file_atomically(folder / "stock.stl", stl_binary(mesh, title));
  if (options.ply) write_file_atomically(folder / "stock.ply", ply_ascii(mesh, title));
  write_file_atomically(folder / "summary.json", summary.dump(2) + "\n");

  for (const PreparedOperation& op : operations) {
    fmt::print(out, "cwe simulate: {} moves of {} with {}\n", op.read.toolpath.moves.size(),
               op.path, op.cutter.name());
  }
  fmt::print(out, "  stock       {} at s = {:g} mm: {} rays, peak {:.1f} MiB ({:.2f} bytes/ray)\n",
             options.stock, simulation.resolution, stock.ray_count(),
             static_cast<double>(memory.peak()) / (1024.0 * 1024.0),
             summary["bytes_per_ray"].get<double>());
  const double cubed = unit.mm * unit.mm * unit.mm;
  fmt::print(out,
             "  removed     {:.{}f} {}³ of {:.{}f} {}³ ({} moves cut material; family spread "
             "{:.{}f} {}³)\n",
             (initial.mean() - final_volume.mean()) / cubed, 1 + 2 * unit.extra_decimals,
             unit.name, initial.mean() / cubed, 1 + 2 * unit.extra_decimals, unit.name,
             removal.cutting_moves, final_volume.spread() / cubed, 2 + 2 * unit.extra_decimals,
             unit.name);
  if (!options.stock_only) {
    fmt::print(out,
               "  engagement  {} cutter locations, {} engaged; deepest {:.{}f} {}, largest "
               "contact {:.{}f} {}²\n",
               cl_points, engaged_cls, unit.length(deepest), 2 + unit.extra_decimals,
               unit.name, unit.area(largest_area), 1 + 2 * unit.extra_decimals, unit.name);
  }
  if (job.forces) {
    fmt::print(out,
               "  forces      {}: peak {:.0f} N at CL {} ({} line {}), torque up to "
               "{:.2f} N·m, power up to {:.2f} kW\n",
               coefficient_names(job), extremes.force.value, extremes.force.cl,
               std::filesystem::path(extremes.force.file).filename().string(), extremes.force.line,
               extremes.torque.value, extremes.power.value / 1000.0);
  }
  fmt::print(out,
             "  accuracy    exact sweeps for linear moves; arcs, helices, 5-axis within "
             "{:g} mm\n",
             removal.deviation_bound);
  fmt::print(out, "  time        {:.2f} s on {} threads\n", seconds, threads);
  if (!removal.rapid_cuts.empty()) {
    const RapidCut& first = removal.rapid_cuts.front();
    fmt::print(out,
               "  warning     {} rapid moves cut material (first: {} line {}); see "
               "summary.json\n",
               removal.rapid_cuts.size(), first.location.source, first.location.line);
  }
  if (warning_count > 0) {
    fmt::print(out, "  warning     the toolpath readers reported {} warnings; see summary.json\n",
               warning_count);
  }
  if (!options.stock_only) {
    fmt::print(out,
               "  outputs     {0}/engagement.csv (one row per cutter location), "
               "{0}/engagement.jsonl (per-disc angles),\n"
               "              {0}/maps/ ({1} engagement maps, path.png along the path),\n",
               options.out, maps_written);
    if (job.forces) {
      fmt::print(out,
                 "              {0}/forces.csv (forces, torque, power per cutter location){1},\n",
                 options.out,
                 curves_written > 0
                     ? fmt::format(", {}/force_curves/ ({} curves)", options.out, curves_written)
                     : std::string());
    }
  }
  fmt::print(out,
             "  {}{}/stock.stl (machined stock, {} triangles on a {:g} mm lattice){}, "
             "{}/summary.json\n",
             options.stock_only ? "outputs     " : "            ", options.out,
             mesh.triangles.size(), stride * simulation.resolution,
             options.ply ? fmt::format(", {}/stock.ply", options.out) : std::string(), options.out);
  return 0;
}

}  // namespace cwe::app
