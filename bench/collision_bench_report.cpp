#include "bench/collision_bench_report.h"

#include "bench/bench_format.h"
#include "core/atomic_file.h"
#include "core/numbers.h"
#include "core/version.h"
#include "studies/reports/svg_plot.h"

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <ostream>
#include <sstream>
#include <thread>

namespace hipfai::bench {

namespace {

using hipfai::kNaN;

double fit_exponent(const std::vector<std::pair<double, double>>& points) {
  std::vector<std::pair<double, double>> logs;
  for (const auto& [x, y] : points) {
    if (x > 0.0 && y > 0.0) logs.emplace_back(std::log10(x), std::log10(y));
  }
  if (logs.size() < 2) return kNaN;
  double mx = 0.0, my = 0.0;
  for (const auto& [x, y] : logs) {
    mx += x;
    my += y;
  }
  mx /= static_cast<double>(logs.size());
  my /= static_cast<double>(logs.size());
  double sxy = 0.0, sxx = 0.0;
  for (const auto& [x, y] : logs) {
    sxy += (x - mx) * (y - my);
    sxx += (x - mx) * (x - mx);
  }
  return sxx > 0.0 ? sxy / sxx : kNaN;
}

void write_lines(const std::filesystem::path& path, const std::vector<std::string>& lines) {
  write_file_atomically(path, [&lines](std::ostream& out) {
    for (const auto& line : lines) out << line << '\n';
  });
}

studies::Series series_of(const std::string& name, const std::vector<std::pair<double, double>>& points, bool dashed = false) {
  studies::Series s;
  s.name = name;
  s.dashed = dashed;
  for (const auto& [x, y] : points) {
    s.x.push_back(x);
    s.y.push_back(y);
  }
  return s;
}

// A chart with log axes (log_y too unless `linear_y`), written as `file` in `dir` and listed in
// `plots` after `fill` adds its series.
void write_chart(const std::string& title, const std::string& x_label, const std::string& y_label, bool linear_y,
                 const std::function<void(studies::LineChart&)>& fill, const std::filesystem::path& dir,
                 const std::string& file, std::vector<std::string>& plots) {
  studies::LineChart chart;
  chart.title = title;
  chart.x_label = x_label;
  chart.y_label = y_label;
  chart.log_x = true;
  chart.log_y = !linear_y;
  fill(chart);
  studies::write_svg(chart, dir / file);
  plots.push_back(file);
}

// What the figures and scaling stages hand to report.md.
struct ReportParts {
  std::vector<std::string> scaling_md;  // rows of the scaling table
  std::vector<std::string> plots;       // SVG files written, in the order report.md shows them
};

// results.csv, the sweep tables and rom_table7.csv.
void write_tables(const CollisionBenchResults& results, const std::filesystem::path& dir) {
  // results.csv
  std::vector<std::string> csv{
      "family,scenario,level,total_vertices,mobile_vertices,fixed_triangles,method,threads,"
      "pre_median_ms,pre_min_ms,pre_max_ms,query_median_ms,query_min_ms,query_max_ms,query_repeats,total_ms,"
      "peak_rss_growth_mib,heap_growth_mib,ratio_query_to_ours,ratio_total_to_ours,reported_vertices,false_negatives,false_positives,"
      "max_depth_error_mm,reference,note"};
  for (const auto& r : results.rows) {
    std::ostringstream line;
    line << r.family << ',' << r.scenario << ',' << r.level << ',' << r.vertices << ',' << r.mobile_vertices << ','
         << r.fixed_triangles << ',' << r.method << ',' << r.threads << ',' << fmt(r.pre.median_ms, 6) << ','
         << fmt(r.pre.min_ms, 6) << ',' << fmt(r.pre.max_ms, 6) << ',' << fmt(r.query.median_ms, 6) << ','
         << fmt(r.query.min_ms, 6) << ',' << fmt(r.query.max_ms, 6) << ',' << r.query.repeats << ','
         << fmt(r.total_ms(), 6) << ',' << fmt(r.memory.peak_rss_growth_mib, 4) << ','
         << fmt(r.memory.heap_growth_mib, 4) << ',' << fmt(r.ratio_query, 4) << ','
         << fmt(r.ratio_total, 4) << ',' << r.exact.reported << ',' << fmt_count(r.exact.false_negatives) << ','
         << fmt_count(r.exact.false_positives) << ',' << fmt(r.exact.max_depth_error_mm, 3) << ",\"" << r.reference << "\",\""
         << r.note << '"';
    csv.push_back(line.str());
  }
  write_lines(dir / "results.csv", csv);
  if (!results.sweep_radial_table_csv.empty()) write_lines(dir / "sweep_radial_table.csv", results.sweep_radial_table_csv);
  if (!results.sweep_cylindrical_csv.empty()) write_lines(dir / "sweep_cylindrical_resolution.csv", results.sweep_cylindrical_csv);
  if (!results.sweep_stepping_csv.empty()) write_lines(dir / "sweep_stepping.csv", results.sweep_stepping_csv);
  {
    std::vector<std::string> lines{"scenario,total_vertices,range_finder_ms,fcl_1deg_ms,spatial_hash_1deg_ms,ratio_fcl,ratio_hash,"
                                   "exact_anticlockwise_deg,exact_clockwise_deg,fcl_anticlockwise_deg,fcl_clockwise_deg,"
                                   "hash_anticlockwise_deg,hash_clockwise_deg,finder_vs_oracle"};
    for (const auto& t : results.rom_table) {
      lines.push_back(t.scenario + "," + std::to_string(t.vertices) + "," + fmt(t.finder_ms, 6) + "," + fmt(t.fcl_ms, 6) + "," +
                      fmt(t.hash_ms, 6) + "," + fmt(t.fcl_ms / t.finder_ms, 4) + "," + fmt(t.hash_ms / t.finder_ms, 4) + "," +
                      fmt(t.exact_ccw, 8) + "," + fmt(t.exact_cw, 8) + "," + fmt(t.fcl_ccw, 8) + "," + fmt(t.fcl_cw, 8) + "," +
                      fmt(t.hash_ccw, 8) + "," + fmt(t.hash_cw, 8) + ",\"" + t.finder_exact + "\"");
    }
    write_lines(dir / "rom_table7.csv", lines);
  }
}

// scaling.csv and one log-log figure per family: query time vs vertices, fitted exponents.
void write_scaling(const CollisionBenchResults& results, const std::filesystem::path& dir, ReportParts& parts) {
  auto& scaling_md = parts.scaling_md;
  auto& plots = parts.plots;
  // Scaling: query (and pre-processing) time vs total vertex count per family / method / threads.
  std::vector<std::string> scaling{"family,method,threads,stage,exponent,points"};
  for (const std::string family : {"striking_hip", "sphere_cube", "cartilage"}) {
    std::map<std::pair<std::string, int>, std::vector<const BenchRow*>> by_method;
    for (const auto& r : results.rows) {
      if (r.family == family && r.method != "oracle") by_method[{r.method, r.threads}].push_back(&r);
    }
    studies::LineChart chart;
    chart.title = family + ": per-pose query time vs vertices (1 thread)";
    chart.x_label = "total vertices";
    chart.y_label = "query time (ms)";
    chart.log_x = chart.log_y = true;
    for (const auto& [key, list] : by_method) {
      std::vector<std::pair<double, double>> query, pre;
      for (const BenchRow* r : list) {
        query.emplace_back(static_cast<double>(r->vertices), r->query.median_ms);
        pre.emplace_back(static_cast<double>(r->vertices), r->pre.median_ms);
      }
      const double eq = fit_exponent(query), ep = fit_exponent(pre);
      scaling.push_back(family + "," + key.first + "," + std::to_string(key.second) + ",query," + fmt(eq, 4) + "," + std::to_string(query.size()));
      scaling.push_back(family + "," + key.first + "," + std::to_string(key.second) + ",pre," + fmt(ep, 4) + "," + std::to_string(pre.size()));
      scaling_md.push_back("| " + family + " | " + key.first + " | " + std::to_string(key.second) + " | " + fmt(eq) + " | " + fmt(ep) + " | " + std::to_string(query.size()) + " |");
      if (key.second == 1) chart.series.push_back(series_of(key.first + " (n^" + fmt(eq, 2) + ")", query));
    }
    if (!chart.series.empty()) {
      const std::string file = "scaling_" + family + ".svg";
      studies::write_svg(chart, dir / file);
      plots.push_back(file);
    }
  }
  write_lines(dir / "scaling.csv", scaling);
}

// The sweeps' figures: radial table size, Maciel's miss rate, ring resolution, stepping error.
void write_sweep_figures(const CollisionBenchResults& results, const std::filesystem::path& dir, ReportParts& parts) {
  if (!results.radial_sweep_query.empty()) {
    write_chart("Radial table size vs time (sphere-cube)", "table cells", "time (ms)", false, [&](studies::LineChart& chart) {
      for (const auto& [method, points] : results.radial_sweep_query) chart.series.push_back(series_of(method + " query", points));
      for (const auto& [method, points] : results.radial_sweep_pre) {
        chart.series.push_back(series_of(method + " pre-processing", points, true));
      }
      chart.series.push_back(series_of("maciel query", results.maciel_query));
    }, dir, "sweep_radial_table.svg", parts.plots);
    write_chart("Maciel ray-based sampling: miss rate vs table size", "table cells", "missed penetrating vertices (%)", true,
                [&](studies::LineChart& chart) { chart.series.push_back(series_of("maciel miss rate", results.maciel_miss)); },
                dir, "sweep_maciel_miss_rate.svg", parts.plots);
  }
  if (!results.cylindrical_sweep.empty()) {
    write_chart("Cylindrical ring resolution vs time (exact at every resolution)", "ring resolution (mm)", "time (ms)", false,
                [&](studies::LineChart& chart) {
                  for (const auto& [name, points] : results.cylindrical_sweep) {
                    chart.series.push_back(series_of(name, points, name != "query"));
                  }
                }, dir, "sweep_cylindrical_resolution.svg", parts.plots);
  }
  if (!results.stepping_sweep.empty()) {
    write_chart("Range of motion: error vs time (stepping 10..0.1 deg vs one pass)", "time (ms)",
                "max ROM error (deg; 1e-6 = exact)", false, [&](studies::LineChart& chart) {
                  for (const auto& [name, points] : results.stepping_sweep) chart.series.push_back(series_of(name, points));
                }, dir, "sweep_stepping.svg", parts.plots);
  }
}

void write_report_md(const CollisionBenchResults& results, const std::vector<TargetVerdict>& targets,
                     const ReportParts& parts, const std::filesystem::path& dir) {
  const auto& scaling_md = parts.scaling_md;
  const auto& plots = parts.plots;
  std::ostringstream md;
  md << "# hipfai collision benchmark\n\n";
  md << "`hipfai bench collision" << (results.quick ? " --quick" : "") << "`, hipfai " << kVersion << " (" << kGitSha << "), "
     << std::thread::hardware_concurrency() << " hardware threads. Every ratio is measured in this run, same process.\n"
     << "Times: median of repeated runs [min–max], ms. *pre* = pre-processing (tables, BVHs, hash grids), *query* = one pose "
        "(posing the mobile mesh included where the method needs a posed mesh). Ratio = method / ours (striking: cylindrical_pose_cache, the thesis' main stage of §3.2.3.2 with the crossings pre-computed per axis — the one-pass query on the posed mesh, cylindrical, is listed too; sliding: radial_cube) with the same thread count (FCL and Maciel are single-threaded: compared with ours on 1 thread). "
        "Memory of the pre-processing: peak RSS growth while building / heap retained by the built structure (MiB; "
        "the first misses heap pages malloc reuses, the second misses transient peaks). FN / FP = false negatives / positives vs the oracle; for FCL and "
        "spatial hashing on tetrahedra the vertex set is compared (FCL: vertices of the mobile triangles it reports), "
        "depth error only where the method returns depths; FN, FP and depth error are empty in rows not compared with a "
        "reference (the oracle's own row).\n\n";
  md << "## Targets\n\n| target | met | measured |\n|---|---|---|\n";
  for (const auto& t : targets) md << "| " << t.target << " | " << (t.informational ? "(measure)" : t.met ? "**met**" : "not met") << " | " << t.measured << " |\n";
  md << "\n## Results\n\n";
  std::string current;
  for (const auto& r : results.rows) {
    if (r.scenario != current) {
      current = r.scenario;
      md << "\n### " << r.scenario << " — " << r.vertices << " vertices (mobile " << r.mobile_vertices << ", fixed triangles "
         << r.fixed_triangles << ")\n\n";
      md << "| method | threads | pre ms | query ms | total ms | peak RSS / heap MiB | query ratio | total ratio | reported | FN | FP | max depth err mm | reference | note |\n";
      md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    }
    md << "| " << r.method << " | " << r.threads << " | " << fmt_ms(r.pre) << " | " << fmt_ms(r.query) << " | " << fmt(r.total_ms())
       << " | " << fmt(r.memory.peak_rss_growth_mib) << " / " << fmt(r.memory.heap_growth_mib) << " | " << fmt(r.ratio_query) << " | " << fmt(r.ratio_total) << " | " << r.exact.reported
       << " | " << fmt_count(r.exact.false_negatives) << " | " << fmt_count(r.exact.false_positives) << " | " << fmt(r.exact.max_depth_error_mm) << " | "
       << r.reference << " | " << r.note << " |\n";
  }
  md << "\n## Range of motion: one pass vs stepping (thesis Table 7)\n\n"
     << "| scenario | vertices | range finder ms | FCL 1° ms | hashing 1° ms | FCL / finder | hashing / finder | exact ccw / cw ° | FCL ccw / cw ° | hashing ccw / cw ° | finder vs oracle |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& t : results.rom_table) {
    md << "| " << t.scenario << " | " << t.vertices << " | " << fmt(t.finder_ms) << " | " << fmt(t.fcl_ms) << " | " << fmt(t.hash_ms)
       << " | " << fmt(t.fcl_ms / t.finder_ms) << " | " << fmt(t.hash_ms / t.finder_ms) << " | " << fmt(t.exact_ccw, 6) << " / "
       << fmt(t.exact_cw, 6) << " | " << fmt(t.fcl_ccw) << " / " << fmt(t.fcl_cw) << " | " << fmt(t.hash_ccw) << " / " << fmt(t.hash_cw)
       << " | " << t.finder_exact << " |\n";
  }
  md << "\nStepping detectors: FCL OBBRSS boolean collide (num_max_contacts 1) and spatial hashing of the fixed surface "
        "triangles stopping at the first triangle-triangle intersection (the thesis' Table 7 setup); both include their "
        "pre-processing. Ranges capped at 180°.\n";
  md << "\n## Scaling (fitted exponent of time vs total vertices, log-log least squares)\n\n"
     << "| family | method | threads | query exponent | pre exponent | points |\n|---|---|---|---|---|---|\n";
  for (const auto& line : scaling_md) md << line << '\n';
  md << "\nThe thesis claims O(p) + O(v) for its methods (exponent 1).\n\n## Figures\n\n";
  for (const auto& p : plots) md << "![" << p << "](" << p << ")\n\n";
  md << "## CSV files\n\nresults.csv, sweep_radial_table.csv (with Maciel miss rates), sweep_cylindrical_resolution.csv, "
        "sweep_stepping.csv, rom_table7.csv, scaling.csv.\n";
  if (!results.notes.empty()) {
    md << "\n## Notes\n\n";
    for (const auto& n : results.notes) md << "- " << n << '\n';
  }
  write_file_atomically(dir / "report.md", md.str());
}

}  // namespace

std::filesystem::path write_collision_bench_report(const CollisionBenchResults& results,
                                                   const std::vector<TargetVerdict>& targets,
                                                   const std::filesystem::path& dir) {
  ReportParts parts;
  write_tables(results, dir);
  write_scaling(results, dir, parts);
  write_sweep_figures(results, dir, parts);
  write_report_md(results, targets, parts, dir);
  return dir / "report.md";
}

}  // namespace hipfai::bench
