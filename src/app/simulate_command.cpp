#include "simulate_command.hpp"

#include <chrono>
#include <filesystem>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/io/atomic_file.hpp"
#include "cwe/io/mesh_io.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"
#include "cwe/workpiece/dexel/dexel_mesh.hpp"
#include "tool_choice.hpp"

namespace cwe::app {
namespace {

// Rapid moves listed by line in the report (all are counted).
constexpr std::size_t kRapidCutsListed = 10;

// Fills options not given on the command line from a JSON job file. Paths in the job are
// relative to the job file's folder.
void read_job(SimulateCommandOptions& options) {
  const std::string text = read_text_file(options.job, "job file");
  nlohmann::json job;
  try {
    job = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(SourceLocation{options.job}, fmt::format("not valid JSON: {}", e.what()));
  }
  if (!job.is_object()) throw InputError(SourceLocation{options.job}, "expected a JSON object");
  const std::filesystem::path folder = std::filesystem::path(options.job).parent_path();
  const auto where = [&](const std::string& key) {
    return SourceLocation{fmt::format("{}: \"{}\"", options.job, key)};
  };
  static const char* const kKeys[] = {"stock",     "tool",    "path",        "out", "resolution",
                                      "tolerance", "threads", "mesh_stride", "ply", "comment"};
  for (const auto& [key, value] : job.items()) {
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys)) {
      throw InputError(where(key),
                       "unknown key; expected stock, tool, path, out, resolution, "
                       "tolerance, threads, mesh_stride, ply or comment");
    }
  }
  const auto text_of = [&](const char* key, std::string& field, bool is_path) {
    if (!job.contains(key) || !field.empty()) return;
    if (!job[key].is_string()) throw InputError(where(key), "expected a string");
    std::string value = job[key].get<std::string>();
    if (is_path && !value.empty() && std::filesystem::path(value).is_relative()) {
      value = (folder / value).lexically_normal().string();
    }
    field = value;
  };
  const auto number_of = [&](const char* key, double& field) {
    if (!job.contains(key) || field != 0.0) return;
    if (!job[key].is_number()) throw InputError(where(key), "expected a number");
    field = job[key].get<double>();
  };
  // A stock given as a file is a path; a box is not.
  if (job.contains("stock") && options.stock.empty()) {
    if (!job["stock"].is_string()) throw InputError(where("stock"), "expected a string");
    const std::string stock = job["stock"].get<std::string>();
    text_of("stock", options.stock, stock.rfind("box:", 0) != 0);
  }
  // A tool specification is a path only when it names a JSON tool file.
  if (job.contains("tool") && options.tool.empty()) {
    if (!job["tool"].is_string()) throw InputError(where("tool"), "expected a string");
    const std::string tool = job["tool"].get<std::string>();
    text_of("tool", options.tool, tool.size() > 5 && tool.ends_with(".json"));
  }
  text_of("path", options.path, true);
  text_of("out", options.out, true);
  number_of("resolution", options.resolution);
  number_of("tolerance", options.tolerance);
  if (job.contains("threads") && options.threads == 0) {
    if (!job["threads"].is_number_integer() || job["threads"].get<int>() < 1) {
      throw InputError(where("threads"), "expected a whole number of threads, at least 1");
    }
    options.threads = job["threads"].get<int>();
  }
  if (job.contains("mesh_stride") && options.mesh_stride == 0) {
    if (!job["mesh_stride"].is_number_integer() || job["mesh_stride"].get<int>() < 1) {
      throw InputError(where("mesh_stride"), "expected a whole number, at least 1");
    }
    options.mesh_stride = job["mesh_stride"].get<int>();
  }
  if (job.contains("ply") && !options.ply) {
    if (!job["ply"].is_boolean()) throw InputError(where("ply"), "expected true or false");
    options.ply = job["ply"].get<bool>();
  }
}

void require(const std::string& value, const char* what, const char* option) {
  if (value.empty()) {
    throw InputError(SourceLocation{"cwe simulate"},
                     fmt::format("no {}: give {} or put it in a job file", what, option));
  }
}

// A one-line progress bar, redrawn when the shown percentage changes.
class ProgressBar {
 public:
  explicit ProgressBar(std::ostream* stream) : stream_(stream) {}
  void operator()(std::size_t done, std::size_t total) {
    if (stream_ == nullptr || total == 0) return;
    const int percent = static_cast<int>(100 * done / total);
    if (percent == shown_) return;
    shown_ = percent;
    constexpr int kWidth = 40;
    const int filled = percent * kWidth / 100;
    fmt::print(*stream_, "\rremoving material [{}{}] {:3d}%  move {}/{}", std::string(filled, '#'),
               std::string(kWidth - filled, ' '), percent, done, total);
    if (done == total) fmt::print(*stream_, "\n");
    stream_->flush();
  }

 private:
  std::ostream* stream_;
  int shown_ = -1;
};

}  // namespace

void add_simulate_command(CLI::App& app, SimulateCommandOptions& options) {
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Run a toolpath through a stock (tri-dexel workpiece) and write the machined stock "
      "(stock.stl) and a summary (summary.json). Job options may come from a JSON job file.");
  cmd->add_option("job", options.job,
                  "JSON job file (keys: stock, tool, path, out, resolution, "
                  "tolerance, threads); options below override it");
  cmd->add_option("--stock", options.stock,
                  "box:xmin,ymin,zmin,xmax,ymax,zmax (mm) or a closed STL file");
  cmd->add_option("--tool", options.tool,
                  "Tool specification or JSON tool file (default: the program's own CUTTER)");
  cmd->add_option("--path", options.path, "Toolpath file (G-code or APT CLDATA)");
  cmd->add_option("--out", options.out, "Output folder");
  cmd->add_option("--resolution", options.resolution, "Ray spacing s, mm (default 0.1)");
  cmd->add_option("--tolerance", options.tolerance,
                  "Subdivision tolerance of arcs, helices and 5-axis moves, mm (default s/10)");
  cmd->add_option("--threads", options.threads, "Worker threads (default: all cores)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--mesh-stride", options.mesh_stride,
                  "Contour stock.stl on every k-th ray position (lattice k·s); default: the "
                  "smallest k giving at most about 1,000,000 triangles")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--ply", options.ply,
                "Also write the stock as stock.ply (ASCII, double precision)");
  cmd->add_flag("--quiet", options.quiet, "No progress bar");
}

int run_simulate_command(SimulateCommandOptions options, std::ostream& out,
                         std::ostream* progress) {
  const auto started = std::chrono::steady_clock::now();
  if (!options.job.empty()) read_job(options);
  require(options.stock, "stock", "--stock");
  require(options.path, "toolpath", "--path");
  require(options.out, "output folder", "--out");
  SimulationOptions simulation;
  simulation.resolution = options.resolution != 0.0 ? options.resolution : 0.1;
  simulation.tolerance = options.tolerance;
  if (options.tolerance < 0.0 || !std::isfinite(options.tolerance)) {
    throw InputError(SourceLocation{"--tolerance"},
                     fmt::format("{} mm: expected a positive length", options.tolerance));
  }
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  const tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                        static_cast<std::size_t>(threads));

  const ReadToolpath read = read_toolpath_file(options.path);
  const Toolpath& path = read.toolpath;
  const Cutter cutter = choose_cutter(options.tool, path, options.path);
  const StockSpec stock_spec = parse_stock_spec(options.stock, SourceLocation{"--stock"});
  TriDexel stock = make_stock(stock_spec, simulation);
  const TriDexel::Volume initial = stock.volume();

  ProgressBar bar(options.quiet ? nullptr : progress);
  const RemovalSummary removal =
      remove_toolpath(stock, cutter, path, simulation,
                      [&bar](std::size_t done, std::size_t total) { bar(done, total); });
  const TriDexel::Volume final_volume = stock.volume();
  const TriDexel::Memory memory = stock.memory();
  const int stride =
      options.mesh_stride > 0 ? options.mesh_stride : dexel_mesh_stride(stock, kStockMeshTriangles);
  const TriangleMesh mesh = dexel_mesh(stock, stride);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  nlohmann::json summary;
  summary["resolution_mm"] = simulation.resolution;
  summary["moves"] = removal.moves;
  summary["initial_volume_mm3"] = initial.mean();
  summary["final_volume_mm3"] = final_volume.mean();
  summary["removed_volume_mm3"] = initial.mean() - final_volume.mean();
  summary["rays"] = stock.ray_count();
  summary["peak_memory_bytes"] = memory.peak();
  summary["seconds"] = seconds;
  summary["tool"] = cutter.name();
  summary["path"] = options.path;
  summary["stock"] = options.stock;
  summary["threads"] = threads;
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
  for (const Diagnostic& d : path.warnings) {
    warnings.push_back(
        {{"file", d.location.source}, {"line", d.location.line}, {"message", d.message}});
  }
  summary["toolpath_warnings"] = warnings;

  // Everything is computed: write the outputs, each whole.
  const std::filesystem::path folder(options.out);
  const std::string title = fmt::format("cwe in-process stock after {}", options.path);
  write_file_atomically(folder / "stock.stl", stl_binary(mesh, title));
  if (options.ply) write_file_atomically(folder / "stock.ply", ply_ascii(mesh, title));
  write_file_atomically(folder / "summary.json", summary.dump(2) + "\n");

  fmt::print(out, "cwe simulate: {} moves of {} with {}\n", removal.moves, options.path,
             cutter.name());
  fmt::print(out, "  stock       {} at s = {:g} mm: {} rays, peak {:.1f} MiB ({:.2f} bytes/ray)\n",
             options.stock, simulation.resolution, stock.ray_count(),
             static_cast<double>(memory.peak()) / (1024.0 * 1024.0),
             summary["bytes_per_ray"].get<double>());
  fmt::print(out,
             "  removed     {:.1f} mm³ of {:.1f} mm³ ({} moves cut material; family spread "
             "{:.2f} mm³)\n",
             initial.mean() - final_volume.mean(), initial.mean(), removal.cutting_moves,
             final_volume.spread());
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
  if (!path.warnings.empty()) {
    fmt::print(out, "  warning     the toolpath reader reported {} warnings; see summary.json\n",
               path.warnings.size());
  }
  fmt::print(out,
             "  outputs     {}/stock.stl (machined stock, {} triangles on a {:g} mm "
             "lattice){}, {}/summary.json\n",
             options.out, mesh.triangles.size(), stride * simulation.resolution,
             options.ply ? fmt::format(", {}/stock.ply", options.out) : std::string(), options.out);
  return 0;
}

}  // namespace cwe::app
