#include "simulate_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_invoke.h>
#include <nlohmann/json.hpp>

#include "cli_checks.hpp"
#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/io/atomic_file.hpp"
#include "cwe/io/cl_sink.hpp"
#include "cwe/io/cl_writers.hpp"
#include "cwe/io/mesh_io.hpp"
#include "cwe/io/output_set.hpp"
#include "cwe/io/step.hpp"
#include "cwe/job/run.hpp"
#include "cwe/job/summary.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"
#include "cwe/workpiece/dexel/dexel_mesh.hpp"
#include "job_file.hpp"

namespace cwe::app {
namespace {

// `key`: maps or force_curves, whose errors are at its origin in `job`.
MapChoice parse_maps(const std::string& text, std::size_t cl_count, const Job& job,
                     std::string_view key) {
  MapChoice choice;
  if (text.empty() && key == "maps") {
    choice.every = std::max<std::size_t>(1, (cl_count + 9) / 10);
    choice.engaged_only = true;
    return choice;
  }
  if (text == "none" || text.empty()) return choice;
  const auto number = [&](std::string_view word) {
    std::size_t value = 0;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (word.empty() || ec != std::errc() || end != word.data() + word.size()) {
      throw job.error(key, fmt::format("'{}' in '{}' is not a whole number; expected every:N, "
                                       "cl:i,j,… or none",
                                       word, text));
    }
    return value;
  };
  const std::string_view view(text);
  if (view.starts_with("every:")) {
    choice.every = number(view.substr(6));
    if (choice.every == 0) throw job.error(key, "every:0: expected a period of at least 1");
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
  throw job.error(key, fmt::format("'{}': expected every:N, cl:i,j,… or none", text));
}

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
      ->check(count("a whole number, at least 1"));
  cmd->add_flag("--ply", options.ply,
                "Also write the stock as stock.ply (ASCII, double precision)");
  cmd->add_flag("--off", options.off,
                "Also write the stock as stock.off (ASCII OFF, double precision)");
  cmd->add_option("--maps", options.maps,
                  "Engagement-map figures: every:N, cl:i,j,… (CL indices from 0) or none "
                  "(default: the first engaged CL of each tenth of the path)");
  cmd->add_option("--force-curves", options.force_curves,
                  "Force-versus-angle curves (CSV and plots) in force_curves/: every:N, "
                  "cl:i,j,… or none (default none)");
  cmd->add_flag("--stock-only", options.stock_only,
                "Material removal only: no engagement outputs (faster)");
}

namespace {

// Where the outputs of a run are.
void print_outputs(std::ostream& out, const SimulateCommandOptions& options, bool forces,
                   const nlohmann::json& summary) {
  const std::size_t triangles = summary["stock_mesh"]["triangles"].get<std::size_t>();
  const std::string made =
      summary["stock_mesh"].contains("lattice_mm")
          ? fmt::format("on a {:g} mm lattice", summary["stock_mesh"]["lattice_mm"].get<double>())
      : summary["stock_mesh"].contains("deviation_mm")
          ? fmt::format("within {:g} mm of the solid",
                        summary["stock_mesh"]["deviation_mm"].get<double>())
          : "of the mesh workpiece";
  const std::size_t maps_written =
      summary.contains("engagement") ? summary["engagement"]["maps"].get<std::size_t>() : 0;
  const std::size_t curves_written =
      summary.contains("forces") ? summary["forces"]["curves"].get<std::size_t>() : 0;
  if (!options.stock_only) {
    fmt::print(out,
               "  outputs     {0}/engagement.csv (one row per cutter location), "
               "{0}/engagement.jsonl (per-disc angles),\n"
               "              {0}/maps/ ({1} engagement maps, path.png along the path),\n",
               options.out, maps_written);
    if (forces) {
      fmt::print(out,
                 "              {0}/forces.csv (forces, torque, power per cutter location){1},\n",
                 options.out,
                 curves_written > 0
                     ? fmt::format(", {}/force_curves/ ({} curves)", options.out, curves_written)
                     : std::string());
    }
  }
  fmt::print(out,
             "  {}{}/stock.stl (machined stock, {} triangles {}){}{}{}, "
             "{}/summary.json\n",
             options.stock_only ? "outputs     " : "            ", options.out, triangles, made,
             options.ply ? fmt::format(", {}/stock.ply", options.out) : std::string(),
             options.off ? fmt::format(", {}/stock.off", options.out) : std::string(),
             summary.contains("stock_solid")
                 ? fmt::format(", {}/{} (the solid)", options.out,
                               summary["stock_solid"]["file"].get<std::string>())
                 : std::string(),
             options.out);
}

// The terminal report of a run: what ran, volumes, engagement and force extremes, accuracy,
// time, warnings and where the outputs are (lengths in `unit`).
void print_report(std::ostream& out, const SimulateCommandOptions& options, const PreparedJob& job,
                  const JobResult& run, const nlohmann::json& summary, const ReportUnit& unit) {
  const std::vector<PreparedOperation>& operations = job.operations;
  const SimulationOptions& simulation = job.simulation;
  const TriDexel::Volume& initial = run.initial_volume;
  const TriDexel::Volume& final_volume = run.final_volume;
  const RemovalSummary& removal = run.removal;
  const ForceExtremes& extremes = run.extremes;
  const std::size_t cl_points = run.cl_points, engaged_cls = run.engaged_cl_points;
  const double deepest = run.deepest, largest_area = run.largest_area;
  const double seconds = summary["seconds"].get<double>();
  const int threads = job.threads;
  std::size_t warning_count = 0;
  for (const PreparedOperation& op : operations) warning_count += op.toolpath.warnings.size();
  for (const PreparedOperation& op : operations) {
    fmt::print(out, "cwe simulate: {} moves of {} with {}\n", op.moves.size(),
               op.path, op.cutter.name());
  }
  const double cubed = unit.mm * unit.mm * unit.mm;
  if (job.stock.step) {
    const StepModel& step = *job.stock.step;
    fmt::print(out,
               "  STEP stock  {} solid{} in {}, {:.{}f} {}³ exact; tessellated within {:g} mm\n",
               step.solids(), step.solids() == 1 ? "" : "s", step.file_unit(),
               step.volume() / cubed, 1 + 2 * unit.extra_decimals, unit.name,
               step_tessellation(simulation, job.workpiece == WorkpieceKind::kMesh));
  }
  if (job.stock.mesh_solid) {
    const StepModel& solid = *job.stock.mesh_solid;
    fmt::print(out, "  STL stock   {} triangles made {} solid{}, {:.{}f} {}³ exact\n",
               job.stock.mesh->triangles.size(), solid.solids(), solid.solids() == 1 ? "" : "s",
               solid.volume() / cubed, 1 + 2 * unit.extra_decimals, unit.name);
  }
  if (run.stock) {
    const TriDexel::Memory memory = run.stock->memory();
    fmt::print(out,
               "  stock       {} at s = {:g} mm: {} rays, peak {:.1f} MiB ({:.2f} bytes/ray)\n",
               options.stock, simulation.resolution, run.stock->ray_count(),
               static_cast<double>(memory.peak()) / (1024.0 * 1024.0),
               summary["bytes_per_ray"].get<double>());
    fmt::print(out,
               "  removed     {:.{}f} {}³ of {:.{}f} {}³ ({} moves cut material; family spread "
               "{:.{}f} {}³)\n",
               (initial.mean() - final_volume.mean()) / cubed, 1 + 2 * unit.extra_decimals,
               unit.name, initial.mean() / cubed, 1 + 2 * unit.extra_decimals, unit.name,
               removal.cutting_moves, final_volume.spread() / cubed, 2 + 2 * unit.extra_decimals,
               unit.name);
  } else if (run.brep) {
    fmt::print(out, "  stock       {} as an exact solid (B-rep): {} faces\n", options.stock,
               run.brep->faces());
    fmt::print(out, "  removed     {:.{}f} {}³ of {:.{}f} {}³ ({} moves cut material)\n",
               (initial.mean() - final_volume.mean()) / cubed, 3 + 2 * unit.extra_decimals,
               unit.name, initial.mean() / cubed, 3 + 2 * unit.extra_decimals, unit.name,
               removal.cutting_moves);
  } else {
    fmt::print(out, "  stock       {} as a triangle mesh, {:g} mm facets: {} triangles\n",
               options.stock, job.facet, run.mesh->triangles());
    fmt::print(out, "  removed     {:.{}f} {}³ of {:.{}f} {}³ ({} moves cut material)\n",
               (initial.mean() - final_volume.mean()) / cubed, 1 + 2 * unit.extra_decimals,
               unit.name, initial.mean() / cubed, 1 + 2 * unit.extra_decimals, unit.name,
               removal.cutting_moves);
  }
  if (!options.stock_only) {
    fmt::print(out,
               "  engagement  {} cutter locations, {} engaged; deepest {:.{}f} {}, largest "
               "contact {:.{}f} {}²\n",
               cl_points, engaged_cls, unit.length(deepest), 2 + unit.extra_decimals, unit.name,
               unit.area(largest_area), 1 + 2 * unit.extra_decimals, unit.name);
  }
  if (job.forces) {
    fmt::print(out,
               "  forces      {}: peak {:.0f} N at CL {} ({} line {}), torque up to "
               "{:.2f} N·m, power up to {:.2f} kW\n",
               coefficient_names(job), extremes.force.value, extremes.force.cl,
               std::filesystem::path(extremes.force.file).filename().string(), extremes.force.line,
               extremes.torque.value, extremes.power.value / 1000.0);
  }
  if (run.stock) {
    fmt::print(out,
               "  accuracy    exact sweeps for linear moves; arcs, helices, 5-axis within "
               "{:g} mm\n",
               removal.deviation_bound);
  } else if (run.brep) {
    fmt::print(out,
               "  accuracy    exact sweeps for lines, planar arcs and helices; {} 5-axis moves "
               "lofted within {:.2g} mm; {} moves (5-axis, or helices, the sweeps or booleans "
               "refused) as linear pieces within {:g} mm\n",
               run.brep->moves_lofted(), run.brep->worst_loft_deviation(),
               run.brep->moves_in_lines(), removal.deviation_bound);
    if (run.brep->removal_volumes_off() > 0) {
      fmt::print(out,
                 "  warning     {} cuts' removal volumes (what the engagement reads) are off what "
                 "the stock lost by up to {:.2g} %\n",
                 run.brep->removal_volumes_off(), 100.0 * run.brep->worst_removal_volume());
    }
    if (run.brep->removal_volumes_replaced() > 0) {
      fmt::print(out,
                 "  warning     {} cuts' removal volumes did not hold what the stock lost; their "
                 "engagement was read from the stock before the cut\n",
                 run.brep->removal_volumes_replaced());
    }
    if (run.brep->cuts_from_mended_stock() > 0) {
      fmt::print(out,
                 "  warning     {} cuts went wrong with every fuzzy value (the stock grew, or a "
                 "solid was left inside the swept volume); each was cut again from the stock "
                 "mended by OpenCASCADE's ShapeFix\n",
                 run.brep->cuts_from_mended_stock());
    }
  } else {
    fmt::print(out,
               "  accuracy    faceted sweeps ({:g} mm facets at the tool's largest radius); arcs, "
               "helices, 5-axis pieces within {:g} mm\n",
               job.facet, removal.deviation_bound);
  }
  const nlohmann::json& stages = summary["seconds_by_stage"];
  fmt::print(out,
             "  time        {:.2f} s on {} threads (set-up {:.2f} s, simulation {:.2f} s, "
             "closing {:.2f} s)\n",
             seconds, threads, stages["set_up"].get<double>(), stages["simulation"].get<double>(),
             stages["closing"].get<double>());
  if (!removal.rapid_cuts.empty()) {
    const RapidCut& first = removal.rapid_cuts.front();
    fmt::print(out,
               "  warning     {} rapid moves cut material (first: {} line {}); see "
               "summary.json\n",
               removal.rapid_cut_count, first.location.source, first.location.line);
  }
  if (warning_count > 0) {
    fmt::print(out, "  warning     the toolpath readers reported {} warnings; see summary.json\n",
               warning_count);
  }
  for (const Diagnostic& d : job.warnings) fmt::print(out, "  warning     {}\n", d.message);
  print_outputs(out, options, job.forces.has_value(), summary);
}

}  // namespace

// Before the long part: the outputs must not overwrite an input (the folder is replaced whole).
namespace {

// The names `cwe simulate` writes in its folder.
const std::vector<std::string> kSimulateOutputs = {
    "stock.stl",      "stock.ply",        "stock.off",  "stock.step", "summary.json",
    "engagement.csv", "engagement.jsonl", "forces.csv", "maps",       "force_curves"};

// stock.stl's write-back is started after every this many bytes appended.
constexpr std::size_t kWritebackBytes = std::size_t{4} << 20;

}  // namespace

void check_output_folder(const std::filesystem::path& folder, const SimulateCommandOptions& options,
                         const PreparedJob& job) {
  std::vector<std::pair<std::string, std::string>> inputs;  // (path, what)
  if (options.stock.rfind("box:", 0) != 0) inputs.emplace_back(options.stock, "the stock");
  for (const PreparedOperation& op : job.operations) inputs.emplace_back(op.path, "a program");
  for (const auto& [path, what] :
       {std::pair{options.tools, "the tool table"}, std::pair{options.machine, "the machine"},
        std::pair{options.forces, "the cutting coefficients"},
        std::pair{options.tool, "the tool file"}, std::pair{options.job_file, "the job file"}}) {
    if (!path.empty()) inputs.emplace_back(path, what);
  }
  std::error_code ec;
  const auto canonical = [&](const std::filesystem::path& p) {
    return std::filesystem::weakly_canonical(p, ec);
  };
  const std::filesystem::path output = canonical(folder);
  for (const auto& [path, what] : inputs) {
    if (!std::filesystem::exists(path, ec)) continue;  // a bundled material, a tool spec
    const std::filesystem::path input = canonical(path);
    const auto [end, _] = std::mismatch(output.begin(), output.end(), input.begin(), input.end());
    if (end == output.end()) {  // the input is inside the folder, or is it
      throw InputError(options.origin("out"),
                       fmt::format("{} is {}, inside the output folder, which this run replaces: "
                                   "write the outputs elsewhere",
                                   path, what));
    }
  }
}

int run_simulate_command(SimulateCommandOptions options, std::ostream& out,
                         std::ostream* progress) {
  const auto started = std::chrono::steady_clock::now();
  read_job(options);
  require(options.out, "output folder", "--out");
  check_units(options, "report_units", options.report_units);
  PreparedJob job = prepare_job(options);
  if (options.mesh_stride && (*options.mesh_stride < 1 || *options.mesh_stride > 1'000'000)) {
    throw options.error("mesh_stride", fmt::format("{}: expected a whole number, 1 to 1000000",
                                                   *options.mesh_stride));
  }
  const int threads = job.threads;
  const tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                        static_cast<std::size_t>(threads));
  std::vector<PreparedOperation>& operations = job.operations;
  const std::size_t cl_count = job.cl_count;
  if (options.stock_only && job.forces) {
    throw options.error("forces",
                        "forces need the engagement, which --stock-only skips; drop one of them");
  }
  MapChoice maps =
      parse_maps(options.stock_only ? "none" : options.maps, cl_count, options, "maps");
  if (!job.forces && !options.force_curves.empty() && options.force_curves != "none") {
    throw options.error("force_curves", "force curves need --forces");
  }
  MapChoice curves =
      parse_maps(job.forces ? options.force_curves : "none", cl_count, options, "force_curves");
  JobStock initial_stock = make_job_stock(job);  // before any output is opened
  const ReportUnit unit = ReportUnit::of(options.report_units);
  check_output_folder(options.out, options, job);
  OutputSet outputs(options.out, kSimulateOutputs, options.origin("out"));
  const std::filesystem::path& folder = outputs.staging();

  ProgressBar bar(options.quiet ? nullptr : progress);
  std::optional<EngagementFiles> files;
  std::optional<Figures> figures;
  std::vector<ClSink*> sinks;
  if (!options.stock_only) {
    files.emplace(folder, job.forces.has_value(), unit);
    figures.emplace(folder, maps, curves, job.forces.has_value(), cl_count);
    sinks = {&*files, &*figures};
  }
  const auto simulating = std::chrono::steady_clock::now();
  JobResult run = run_job(job, std::move(initial_stock), RunOptions{!options.stock_only}, sinks,
                          [&](std::size_t done, std::size_t total) { bar(done, total); });
  const auto closing = std::chrono::steady_clock::now();
  const int stride = !run.stock            ? 1
                     : options.mesh_stride ? *options.mesh_stride
                                           : dexel_mesh_stride(*run.stock, kStockMeshTriangles);
  TriangleMesh mesh;
  AtomicFileWriter stl(folder / "stock.stl");
  const std::string stock_title = fmt::format("cwe in-process stock after {}", job_paths(job));
  // The stock's contouring beside the last figures and files (they never read the stock): on
  // one thread they were a serial fifth of a job's time after the parallel engagement. The disk
  // writes each output while the rest is made: the files and figures are synced ahead as soon as
  // they are in place, while the stock is contoured; stock.stl is encoded and written as its
  // triangles are made, its write-back started every few megabytes and its sync as soon as it is
  // whole. The publication waits for them (at its start, they took a few tens of milliseconds
  // with both threads idle).
  tbb::parallel_invoke(
      [&] {
        if (options.stock_only) return;
        files->finish();
        std::vector<std::filesystem::path> made = files->commit();
        const std::string title =
            operations.size() == 1
                ? fmt::format("Engagement along {} with {}",
                              std::filesystem::path(operations[0].path).filename().string(),
                              operations[0].cutter.name())
                : fmt::format("Engagement along {} operations", operations.size());
        figures->finish(title);
        for (std::filesystem::path& path : figures->commit()) made.push_back(std::move(path));
        outputs.sync_ahead(made);
      },
      [&] {
        const auto write = [&stl](std::string_view piece) {
          stl.append(piece);
          if (stl.writeback_pending() >= kWritebackBytes) stl.start_writeback();
        };
        if (run.stock) {
          // The triangles encoded and written as the stock is contoured, on the thread that the
          // contouring leaves spare; the rest once it has finished, and the count last.
          write(stl_binary_header(stock_title, 0));
          FollowedMesh made = dexel_mesh(*run.stock, stride,
                                         [&write](std::span<const std::array<int, 3>> triangles,
                                                  std::span<const Vec3> vertices) {
                                           stl_binary_facets(triangles, vertices, write);
                                         });
          mesh = std::move(made.mesh);
          stl_binary_facets(std::span(mesh.triangles).subspan(made.followed), mesh.vertices, write);
          stl.overwrite(0, stl_binary_header(stock_title, mesh.triangles.size()));
        } else {
          mesh = run.mesh ? run.mesh->mesh()
                          : tessellate(*run.brep, step_tessellation(job.simulation, false));
          stl_binary(mesh, stock_title, write);
        }
        stl.commit();  // starts the rest's write-back
        outputs.sync_ahead({stl.path()});
      });
  const std::size_t maps_written = figures ? figures->maps_written() : 0;
  const std::size_t curves_written = figures ? figures->curves_written() : 0;
  const auto done = std::chrono::steady_clock::now();
  const auto seconds_between = [](auto from, auto to) {
    return std::chrono::duration<double>(to - from).count();
  };

  JobSummary extras;
  extras.stock = options.stock;
  extras.report_units = unit.name;
  extras.set_up_seconds = seconds_between(started, simulating);
  extras.simulation_seconds = seconds_between(simulating, closing);
  extras.closing_seconds = seconds_between(closing, done);
  extras.mesh_stride = stride;
  extras.mesh = &mesh;
  extras.ply = options.ply;
  extras.off = options.off;
  extras.engagement = !options.stock_only;
  extras.maps = maps_written;
  extras.curves = curves_written;
  const std::string summary_text = job_summary(job, run, extras);
  const nlohmann::json summary = nlohmann::json::parse(summary_text);

  // Everything is computed: the last outputs, each whole; the summary last.
  if (options.ply) write_file_atomically(folder / "stock.ply", ply_ascii(mesh, stock_title));
  if (options.off) write_file_atomically(folder / "stock.off", off_ascii(mesh, stock_title));
  if (run.brep) write_file_atomically(folder / "stock.step", step_bytes(*run.brep));
  // The report, printed once the outputs are published. The workpiece and its mesh are freed
  // now, while stock.stl's sync waits for the disk, not one after the other at exit.
  std::ostringstream report;
  print_report(report, options, job, run, summary, unit);
  run.stock.reset();
  run.mesh.reset();
  run.brep.reset();
  mesh = {};
  write_file_atomically(folder / "summary.json", summary_text);
  outputs.publish();

  out << report.str();
  return 0;
}

}  // namespace cwe::app
