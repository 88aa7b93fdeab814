#include "compare_command.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/io/atomic_file.hpp"
#include "cwe/io/engagement_plot.hpp"
#include "cwe/io/line_plot.hpp"
#include "cwe/io/output_set.hpp"
#include "cwe/job/compare.hpp"
#include "cwe/job/run.hpp"
#include "job_file.hpp"

namespace cwe::app {

void add_compare_command(CLI::App& app, CompareCommandOptions& options) {
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "Run one job on several in-process workpieces and compare their engagement at every "
      "cutter location against the reference (B-rep when it runs, else the first): writes "
      "compare.csv and compare.json (docs/accuracy.md).");
  add_job_options(cmd, options);
  cmd->add_option("--workpieces", options.workpieces,
                  "The workpieces to run, comma-separated: dexel, mesh, brep (one may come twice, "
                  "as a check); default dexel,mesh,brep");
  cmd->add_option("--sweep-resolution", options.sweep_resolution,
                  "Convergence: run each workpiece but the reference at each of these resolutions "
                  "(mm, comma-separated; the reference at the finest) and write convergence.csv "
                  "and its figures");
  cmd->add_option("--sweep-facet", options.sweep_facet,
                  "Convergence: run the mesh workpiece at each of these facet sizes (mm, "
                  "comma-separated) against the reference");
  cmd->add_option("--out", options.out, "Output folder");
}

namespace {

const std::vector<std::string> kCompareOutputs = {"compare.csv",          "compare.json",
                                                  "differences.png",      "differences.svg",
                                                  "convergence.csv",      "convergence.png",
                                                  "convergence.svg",      "convergence_time.png",
                                                  "convergence_time.svg", "maps"};

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// The process's resident memory, bytes, as /proc/self/status gives it under `field` ("VmRSS:"
// now, "VmHWM:" at its peak); 0 where it does not tell.
std::size_t resident_memory(const std::string& field) {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind(field, 0) == 0) return std::stoull(line.substr(field.size())) * 1024;
  }
  return 0;
}

// Starts the peak over (Linux: writing 5 to clear_refs); false where it cannot, when each run's
// peak is the process's so far.
bool reset_peak_memory() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

struct Method {
  std::string workpiece;  // dexel, mesh, brep
  std::string label;      // the workpiece, with _2, _3 when it comes again, or its setting
  std::optional<double> resolution, facet;  // a sweep's setting (else the job's)
  std::optional<PreparedJob> job;
  std::vector<ClRecord> records;
  double removed = 0.0;  // mm³
  double seconds = 0.0, cpu = 0.0;
  // The process's resident memory when the run started (the runs before keep their maps) and
  // at its peak during the run (or since the process started, where it cannot be reset).
  std::size_t held = 0, peak = 0;
  bool peak_of_run = false;
  std::size_t own() const { return peak > held ? peak - held : 0; }
};

// The positive lengths of a comma-separated list given to `option`.
std::vector<double> lengths(const std::string& text, const char* option) {
  std::vector<double> values;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    double value = 0.0;
    std::size_t used = 0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !(value > 0.0) || !std::isfinite(value)) {
      throw InputError(SourceLocation{option},
                       fmt::format("'{}' in '{}': expected positive lengths in mm, "
                                   "comma-separated",
                                   item, text));
    }
    values.push_back(value);
  }
  if (values.empty()) {
    throw InputError(SourceLocation{option}, "expected positive lengths in mm, comma-separated");
  }
  return values;
}

// The runs: the workpieces listed, or with a sweep the reference once and each other workpiece
// at each setting. The reference is the B-rep run when there is one, else the first.
std::vector<Method> methods_of(const CompareCommandOptions& options, std::size_t& reference) {
  std::vector<std::string> names;
  std::stringstream list(options.workpieces);
  for (std::string name; std::getline(list, name, ',');) {
    if (name != "dexel" && name != "mesh" && name != "brep") {
      throw InputError(SourceLocation{"--workpieces"},
                       fmt::format("'{}' is not a workpiece; expected dexel, mesh or brep", name));
    }
    names.push_back(name);
  }
  if (names.size() < 2) {
    throw InputError(
        SourceLocation{"--workpieces"},
        fmt::format("'{}': expected at least two workpieces to compare", options.workpieces));
  }
  const auto brep = std::find(names.begin(), names.end(), "brep");
  reference = brep != names.end() ? static_cast<std::size_t>(brep - names.begin()) : 0;
  const bool by_resolution = !options.sweep_resolution.empty();
  const bool by_facet = !options.sweep_facet.empty();
  std::vector<Method> methods;
  const auto add = [&](const std::string& name, const std::string& label) {
    Method m;
    m.workpiece = name;
    m.label = label;
    methods.push_back(std::move(m));
    return &methods.back();
  };
  if (!by_resolution && !by_facet) {
    for (std::size_t k = 0; k < names.size(); ++k) {
      const auto seen = std::count(names.begin(), names.begin() + static_cast<long>(k), names[k]);
      add(names[k], seen == 0 ? names[k] : fmt::format("{}_{}", names[k], seen + 1));
    }
    return methods;
  }
  if (by_resolution && by_facet) {
    throw InputError(SourceLocation{"--sweep-facet"},
                     "one sweep at a time: give --sweep-resolution or --sweep-facet");
  }
  const char* option = by_resolution ? "--sweep-resolution" : "--sweep-facet";
  const std::vector<double> settings =
      lengths(by_resolution ? options.sweep_resolution : options.sweep_facet, option);
  Method* ref = add(names[reference], names[reference]);
  if (by_resolution) ref->resolution = *std::min_element(settings.begin(), settings.end());
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k == reference) continue;
    if (by_facet && names[k] != "mesh") {
      throw InputError(SourceLocation{option},
                       fmt::format("the facet size is the mesh workpiece's; {} has none (list "
                                   "mesh and the reference in --workpieces)",
                                   names[k]));
    }
    for (const double value : settings) {
      Method* m =
          add(names[k], fmt::format("{}_{}{:g}", names[k], by_resolution ? "s" : "f", value));
      (by_resolution ? m->resolution : m->facet) = value;
    }
  }
  reference = 0;
  return methods;
}

// A CSV cell holding `text` whatever it holds: quoted, quotes doubled (RFC 4180).
std::string csv_text(const std::string& text) {
  std::string cell = "\"";
  for (const char c : text) cell += c == '"' ? std::string("\"\"") : std::string(1, c);
  return cell + "\"";
}

nlohmann::json stats_json(const DifferenceStats& s) {
  return {{"count", s.count}, {"p50", s.p50}, {"p95", s.p95},
          {"p99", s.p99},     {"max", s.max}, {"max_cl", s.max_cl}};
}

constexpr double kDeg = 180.0 / kPi;
// The smallest reference area, relative to the job's largest, whose CLs count in the relative
// area differences' percentiles.
constexpr double kLeastArea = 0.01;

}  // namespace

int run_compare_command(CompareCommandOptions options, std::ostream& out, std::ostream* progress) {
  read_job(options);
  require(options.out, "output folder", "--out");
  std::size_t reference = 0;
  std::vector<Method> methods = methods_of(options, reference);
  // Every run prepared (and so checked) before the first starts.
  for (Method& m : methods) {
    Job job = options;
    job.workpiece = m.workpiece;
    if (m.resolution) job.resolution = m.resolution;
    if (m.facet) job.facet = m.facet;
    m.job = prepare_job(job);
  }
  check_output_folder(options.out, options, *methods[0].job);
  OutputSet outputs(options.out, kCompareOutputs, options.origin("out"));
  const tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                        static_cast<std::size_t>(methods[0].job->threads));

  for (Method& m : methods) {
    if (progress != nullptr && !options.quiet) fmt::print(*progress, "{}:\n", m.label);
    ProgressBar bar(options.quiet ? nullptr : progress);
    m.held = resident_memory("VmRSS:");
    m.peak_of_run = reset_peak_memory();
    const auto started = std::chrono::steady_clock::now();
    const double cpu_before = cpu_seconds();
    RecordingSink sink;
    std::vector<ClSink*> sinks = {&sink};
    std::optional<JobResult> run;
    try {
      run.emplace(run_job(*m.job, make_job_stock(*m.job), RunOptions{true, false}, sinks,
                          [&](std::size_t done, std::size_t total) { bar(done, total); }));
    } catch (const ComputationError& e) {
      throw ComputationError(fmt::format("the {} run: {}", m.label, e.what()));
    }
    m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    m.cpu = cpu_seconds() - cpu_before;
    m.peak = resident_memory("VmHWM:");
    m.removed = run->initial_volume.mean() - run->final_volume.mean();
    m.records = std::move(sink.records);
  }

  const Method& ref = methods[reference];
  std::vector<std::vector<ClDifference>> differences(methods.size());
  for (std::size_t k = 0; k < methods.size(); ++k) {
    if (k == reference) continue;
    try {
      differences[k] = compare_runs(*ref.job, ref.records, methods[k].records);
    } catch (const ComputationError& e) {
      throw ComputationError(
          fmt::format("comparing {} with {}: {}", methods[k].label, ref.label, e.what()));
    }
  }

  // compare.csv: a row per CL.
  std::string csv = "cl,operation,file,line,x_mm,y_mm,z_mm";
  for (const Method& m : methods) {
    csv += fmt::format(",{0}_engaged,{0}_entry_deg,{0}_exit_deg,{0}_axial_depth_mm,{0}_area_mm2",
                       m.label);
  }
  for (std::size_t k = 0; k < methods.size(); ++k) {
    if (k == reference) continue;
    csv += fmt::format(
        ",{0}_d_entry_deg,{0}_d_exit_deg,{0}_d_axial_depth_mm,{0}_d_area_mm2,"
        "{0}_exclusive_area_mm2,{0}_exclusive_relative",
        methods[k].label);
  }
  csv += "\n";
  for (std::size_t cl = 0; cl < ref.records.size(); ++cl) {
    const ClRecord& r = ref.records[cl];
    csv += fmt::format("{},{},{},{},{:.6f},{:.6f},{:.6f}", cl, r.operation, csv_text(r.file),
                       r.line, r.position.x(), r.position.y(), r.position.z());
    for (const Method& m : methods) {
      const EngagementMap& map = m.records[cl].map;
      csv += fmt::format(",{},{:.4f},{:.4f},{:.4f},{:.5f}", map.engaged ? 1 : 0,
                         map.phi_entry * kDeg, map.phi_exit * kDeg, map.axial_depth, map.area);
    }
    for (std::size_t k = 0; k < methods.size(); ++k) {
      if (k == reference) continue;
      const ClDifference& d = differences[k][cl];
      const MapDifference& m = d.difference;
      if (m.both_engaged) {
        csv += fmt::format(",{:.4f},{:.4f}", m.entry * kDeg, m.exit * kDeg);
      } else {
        csv += ",,";
      }
      csv += fmt::format(",{:.4f},{:.5f},{:.5f},", m.axial_depth, m.area, m.exclusive_area);
      if (d.reference_area > 0.0) csv += fmt::format("{:.6f}", m.exclusive_area / d.reference_area);
    }
    csv += "\n";
  }

  // compare.json.
  nlohmann::json summary;
  summary["reference"] = ref.label;
  summary["cl_points"] = ref.records.size();
  summary["resolution_mm"] = ref.job->simulation.resolution;
  summary["facet_mm"] = ref.job->facet;
  summary["threads"] = ref.job->threads;
  nlohmann::json runs = nlohmann::json::array();
  for (const Method& m : methods) {
    std::size_t engaged = 0;
    for (const ClRecord& r : m.records) engaged += r.map.engaged;
    runs.push_back({{"label", m.label},
                    {"workpiece", m.workpiece},
                    {"removed_volume_mm3", m.removed},
                    {"removed_volume_difference_mm3", m.removed - ref.removed},
                    {"removed_volume_relative",
                     ref.removed > 0.0 ? (m.removed - ref.removed) / ref.removed : 0.0},
                    {"engaged_cl_points", engaged},
                    {"seconds", m.seconds},
                    {"cpu_seconds", m.cpu},
                    {"peak_memory_bytes", m.peak},
                    {"peak_memory_of", m.peak_of_run ? "this run" : "the process so far"},
                    {"memory_held_before_bytes", m.held},
                    {"run_memory_bytes", m.own()}});
  }
  summary["runs"] = runs;
  nlohmann::json against = nlohmann::json::object();
  const auto both = [](const ClDifference& d) { return d.difference.both_engaged; };
  const auto either = [](const ClDifference& d) { return d.reference_engaged || d.other_engaged; };
  for (std::size_t k = 0; k < methods.size(); ++k) {
    if (k == reference) continue;
    const std::vector<ClDifference>& ds = differences[k];
    std::size_t one_only = 0;
    // Per CL, the surface engaged by one only relative to the reference's engaged area, where
    // that is at least 1 % of the job's largest (at first contact a sliver of either is all of
    // it); over the job, their sums.
    double largest = 0.0, total_exclusive = 0.0, total_reference = 0.0;
    for (const ClDifference& d : ds) {
      one_only += d.reference_engaged != d.other_engaged;
      largest = std::max(largest, d.reference_area);
      total_exclusive += d.difference.exclusive_area;
      total_reference += d.reference_area;
    }
    against[methods[k].label] = {
        {"entry_deg",
         stats_json(difference_stats(
             ds, [](const ClDifference& d) { return d.difference.entry * kDeg; }, both))},
        {"exit_deg",
         stats_json(difference_stats(
             ds, [](const ClDifference& d) { return d.difference.exit * kDeg; }, both))},
        {"axial_depth_mm",
         stats_json(difference_stats(
             ds, [](const ClDifference& d) { return d.difference.axial_depth; }, either))},
        {"area_mm2", stats_json(difference_stats(
                         ds, [](const ClDifference& d) { return d.difference.area; }, either))},
        {"exclusive_area_mm2",
         stats_json(difference_stats(
             ds, [](const ClDifference& d) { return d.difference.exclusive_area; }, either))},
        {"exclusive_relative",
         stats_json(difference_stats(
             ds,
             [](const ClDifference& d) { return d.difference.exclusive_area / d.reference_area; },
             [&](const ClDifference& d) { return d.reference_area >= kLeastArea * largest; }))},
        {"exclusive_total_relative",
         total_reference > 0.0 ? total_exclusive / total_reference : 0.0},
        {"engaged_by_one_only", one_only}};
  }
  summary["differences"] = against;
  const std::string json_text = summary.dump(2) + "\n";

  // The differences along the path: the surface engaged by one method only, at every CL.
  LinePlot along;
  along.title = fmt::format("Engaged surface that differs from {}", ref.label);
  along.x_label = "CL index";
  along.y_label = "engaged by one only (mm²)";
  for (std::size_t k = 0; k < methods.size(); ++k) {
    if (k == reference) continue;
    PlotSeries series{methods[k].label, {}, {}};
    for (const ClDifference& d : differences[k]) {
      series.x.push_back(static_cast<double>(d.cl));
      series.y.push_back(d.difference.exclusive_area);
    }
    along.series.push_back(std::move(series));
  }

  // A sweep: each setting's error and cost, as a table and log-log figures.
  const bool sweep = !options.sweep_resolution.empty() || !options.sweep_facet.empty();
  std::string table;
  LinePlot error, cost;
  if (sweep) {
    const bool by_resolution = !options.sweep_resolution.empty();
    const std::string setting = by_resolution ? "resolution (mm)" : "facet size (mm)";
    table =
        "workpiece,resolution_mm,facet_mm,exclusive_total_relative,exclusive_relative_p95,"
        "entry_p95_deg,exit_p95_deg,axial_depth_p95_mm,removed_volume_relative,seconds,"
        "cpu_seconds,run_memory_bytes\n";
    error.title = fmt::format("Engaged surface that differs from {} (over the job)", ref.label);
    error.x_label = setting;
    error.y_label = "engaged by one only / engaged (%)";
    error.log_x = error.log_y = true;
    cost.title = "Cost of each run";
    cost.x_label = setting;
    cost.y_label = "CPU time (s)";
    cost.log_x = cost.log_y = true;
    for (std::size_t k = 0; k < methods.size(); ++k) {
      if (k == reference) continue;
      const Method& m = methods[k];
      const nlohmann::json& d = against[m.label];
      table += fmt::format(
          "{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.3f},{:.3f},{}\n", m.workpiece,
          m.job->simulation.resolution, m.job->facet, d["exclusive_total_relative"].get<double>(),
          d["exclusive_relative"]["p95"].get<double>(), d["entry_deg"]["p95"].get<double>(),
          d["exit_deg"]["p95"].get<double>(), d["axial_depth_mm"]["p95"].get<double>(),
          ref.removed > 0.0 ? (m.removed - ref.removed) / ref.removed : 0.0, m.seconds, m.cpu,
          m.own());
      const double x = by_resolution ? m.job->simulation.resolution : m.job->facet;
      const auto series_of = [&](LinePlot& plot) -> PlotSeries& {
        for (PlotSeries& s : plot.series) {
          if (s.label == m.workpiece) return s;
        }
        plot.series.push_back({m.workpiece, {}, {}, true});
        return plot.series.back();
      };
      PlotSeries& e = series_of(error);
      e.x.push_back(x);
      e.y.push_back(100.0 * d["exclusive_total_relative"].get<double>());
      PlotSeries& c = series_of(cost);
      c.x.push_back(x);
      c.y.push_back(m.cpu);
    }
    PlotSeries reference_cost{ref.label + " (reference)", {}, {}, true};
    const double at = by_resolution ? ref.job->simulation.resolution : ref.job->facet;
    reference_cost.x = {at};
    reference_cost.y = {ref.cpu};
    cost.series.push_back(std::move(reference_cost));
  }

  write_file_atomically(outputs.staging() / "compare.csv", csv);
  write_file_atomically(outputs.staging() / "differences.png", line_plot_png(along));
  write_file_atomically(outputs.staging() / "differences.svg", line_plot_svg(along));
  if (sweep) {
    write_file_atomically(outputs.staging() / "convergence.csv", table);
    write_file_atomically(outputs.staging() / "convergence.png", line_plot_png(error));
    write_file_atomically(outputs.staging() / "convergence.svg", line_plot_svg(error));
    write_file_atomically(outputs.staging() / "convergence_time.png", line_plot_png(cost));
    write_file_atomically(outputs.staging() / "convergence_time.svg", line_plot_svg(cost));
  }
  // The maps of the CL where each method differs most from the reference, one over the other.
  std::filesystem::create_directories(outputs.staging() / "maps");
  std::vector<std::string> worst;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    if (k == reference) continue;
    const nlohmann::json& largest = against[methods[k].label]["exclusive_area_mm2"];
    if (largest["max"].get<double>() <= 0.0) continue;
    const std::size_t cl = largest["max_cl"].get<std::size_t>();
    const ClRecord& at = ref.records[cl];
    const Cutter& cutter = ref.job->operations[at.operation].cutter;
    MapPlotInfo info;
    info.title = fmt::format("CL {} ({} line {}): {} over {}", cl,
                             std::filesystem::path(at.file).filename().string(), at.line,
                             methods[k].label, ref.label);
    info.tool_radius = cutter.profile().max_radius();
    info.flute_height = cutter.profile().height();
    info.overlay = &methods[k].records[cl].map;
    info.label = ref.label;
    info.overlay_label = methods[k].label;
    const std::string name = fmt::format("cl_{:06d}_{}", cl, methods[k].label);
    write_file_atomically(outputs.staging() / "maps" / (name + ".png"),
                          engagement_map_png(at.map, info));
    write_file_atomically(outputs.staging() / "maps" / (name + ".svg"),
                          engagement_map_svg(at.map, info));
    worst.push_back(name);
  }
  write_file_atomically(outputs.staging() / "compare.json", json_text);
  outputs.publish();

  fmt::print(out, "cwe compare: {} cutter locations, reference {}\n", ref.records.size(),
             ref.label);
  std::size_t width = 0;
  for (const Method& m : methods) width = std::max(width, m.label.size());
  for (const Method& m : methods) {
    fmt::print(out,
               "  {:<{}} removed {:.3f} mm³ ({:+.3g} %), {:.2f} s ({:.2f} s CPU), {:.0f} MiB\n",
               m.label, width, m.removed,
               ref.removed > 0.0 ? 100.0 * (m.removed - ref.removed) / ref.removed : 0.0, m.seconds,
               m.cpu, static_cast<double>(m.own()) / (1024.0 * 1024.0));
  }
  for (std::size_t k = 0; k < methods.size(); ++k) {
    if (k == reference) continue;
    const nlohmann::json& d = against[methods[k].label];
    fmt::print(out,
               "  {} against {}: entry p95 {:.3f}°, exit p95 {:.3f}°, engaged area off p95 "
               "{:.3g} % (largest {:.3g} % at CL {}; over the job {:.3g} %); {} CLs engaged by "
               "one only\n",
               methods[k].label, ref.label, d["entry_deg"]["p95"].get<double>(),
               d["exit_deg"]["p95"].get<double>(),
               100.0 * d["exclusive_relative"]["p95"].get<double>(),
               100.0 * d["exclusive_relative"]["max"].get<double>(),
               d["exclusive_relative"]["max_cl"].get<std::size_t>(),
               100.0 * d["exclusive_total_relative"].get<double>(),
               d["engaged_by_one_only"].get<std::size_t>());
  }
  const std::filesystem::path folder(options.out);
  fmt::print(out,
             "  outputs  {} (per CL), {} (runs, percentiles), {} (along the path), {} ({} maps "
             "where the methods differ most, overlaid){}\n",
             (folder / "compare.csv").string(), (folder / "compare.json").string(),
             (folder / "differences.png").string(), (folder / "maps").string(), worst.size(),
             sweep ? fmt::format(", {} and its figures", (folder / "convergence.csv").string())
                   : std::string());
  return 0;
}

}  // namespace cwe::app
