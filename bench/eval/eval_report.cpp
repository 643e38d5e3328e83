// Plots with gnuplot (SVG terminal; Debian's gnuplot-nox) and a Markdown page with the results table.
#include "eval_report.hpp"

#include "cli/exit_codes.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace dhr::eval {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Row {
  std::string method;
  double rtt_ms = 0, bit_error = 0, ssim = 0, psnr = 0, unknown_frac = 0, client_ms = 0, server_ms = 0;
  double bytes_per_frame = 0, response_ms = 0, frames_behind = 0, frames_predicted = 0;
  double visibility_error = 0, rays_per_pixel = 0;
  int x_max = -1, guard_px = 0;
  std::string guard;
  bool psnr_inf = false;
  bool has_flip = false;  // null in results.json: FLIP was not computed
  double flip = 0;
  double frame_ms() const { return 2.0 * (client_ms + server_ms); }  // both eyes, client + server
  std::string x_max_text() const { return x_max < 0 ? "all" : std::to_string(x_max); }
};

struct Series {
  std::string title;
  std::vector<std::pair<double, double>> points;
};

double num(const json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : 0.0;
}

std::vector<Row> read_rows(const json& results) {
  std::vector<Row> rows;
  for (const json& j : results) {
    Row r;
    r.method = j.value("method", "");
    r.rtt_ms = num(j, "rtt_ms");
    r.x_max = j.value("x_max", -1);
    r.guard = j.value("guard", "");
    r.guard_px = static_cast<int>(num(j, "guard_px_x"));
    r.bit_error = num(j, "bit_error");
    r.visibility_error = num(j, "visibility_error");
    r.rays_per_pixel = num(j, "server_rays_per_pixel");
    r.ssim = num(j, "ssim");
    r.psnr_inf = j.contains("psnr") && j["psnr"].is_null();
    r.psnr = num(j, "psnr");
    r.has_flip = j.contains("flip") && j["flip"].is_number();
    r.flip = num(j, "flip");
    r.unknown_frac = num(j, "unknown_frac");
    r.client_ms = num(j, "client_ms");
    r.server_ms = num(j, "server_ms");
    r.bytes_per_frame = num(j, "bytes_per_frame");
    r.response_ms = num(j, "response_ms");
    r.frames_behind = num(j, "frames_behind");
    r.frames_predicted = num(j, "frames_predicted");
    rows.push_back(r);
  }
  return rows;
}

std::string fmt(int decimals, double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

// Writes NAME.dat and NAME.gp and runs gnuplot; returns the SVG's file name, or "" when nothing was drawn.
std::string plot(const fs::path& dir, const std::string& name, const std::string& title, const std::string& xlabel,
                 const std::string& ylabel, std::vector<Series> series, bool lines = true) {
  series.erase(std::remove_if(series.begin(), series.end(), [](const Series& s) { return s.points.empty(); }),
               series.end());
  if (series.empty()) return "";
  std::ofstream dat(dir / (name + ".dat"));
  for (Series& s : series) {
    if (lines) std::sort(s.points.begin(), s.points.end());
    dat << "# " << s.title << "\n";
    for (const auto& [x, y] : s.points) dat << x << " " << y << "\n";
    dat << "\n\n";
  }
  dat.close();
  std::ofstream gp(dir / (name + ".gp"));
  gp << "set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'\n"
     << "set output '" << (dir / (name + ".svg")).string() << "'\n"
     << "set title '" << title << "' noenhanced\nset xlabel '" << xlabel << "' noenhanced\nset ylabel '" << ylabel
     << "' noenhanced\nset key outside right top noenhanced\nset grid\n";
  gp << "plot ";
  for (size_t i = 0; i < series.size(); ++i) {
    gp << (i ? ", " : "") << "'" << (dir / (name + ".dat")).string() << "' index " << i << " using 1:2 with "
       << (lines ? "linespoints" : "points") << " pt " << (i % 7) + 1 << " title '" << series[i].title << "'";
  }
  gp << "\n";
  gp.close();
  const std::string command = "gnuplot '" + (dir / (name + ".gp")).string() + "' 2>&1";
  if (std::system(command.c_str()) != 0) {
    std::fprintf(stderr, "dhr-eval: gnuplot failed for %s (is gnuplot installed?)\n", name.c_str());
    return "";
  }
  return name + ".svg";
}

// Series keyed by a label, in first-seen order.
struct SeriesSet {
  std::vector<Series> list;
  Series& at(const std::string& title) {
    for (Series& s : list) {
      if (s.title == title) return s;
    }
    list.push_back(Series{title, {}});
    return list.back();
  }
};

// Settings on the lower-left front: no other setting is both faster and more accurate.
std::vector<std::pair<double, double>> pareto_front(const std::vector<Row>& rows) {
  std::vector<std::pair<double, double>> pts;
  for (const Row& r : rows) pts.emplace_back(r.frame_ms(), r.bit_error);
  std::sort(pts.begin(), pts.end());
  std::vector<std::pair<double, double>> front;
  double best = INFINITY;
  for (const auto& p : pts) {
    if (p.second < best) {
      front.push_back(p);
      best = p.second;
    }
  }
  return front;
}

}  // namespace

int write_report(const std::string& dir_text) {
  const fs::path dir(dir_text);
  json results, run;
  try {
    std::ifstream rf(dir / "results.json");
    if (!rf) throw std::runtime_error((dir / "results.json").string() + ": cannot open");
    results = json::parse(rf);
    std::ifstream mf(dir / "run.json");
    if (mf) run = json::parse(mf);
    if (!results.is_array()) throw std::runtime_error("results.json: expected a list");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dhr-eval: %s\n", e.what());
    return exit_code::kUsage;  // the results the command line names are missing or malformed
  }
  const std::vector<Row> rows = read_rows(results);
  if (rows.empty()) {
    std::fprintf(stderr, "dhr-eval: %s: no results\n", (dir / "results.json").string().c_str());
    return exit_code::kUsage;
  }
  const std::string first_guard = rows.front().guard;
  bool several_x = false, several_guards = false;
  for (const Row& r : rows) {
    several_guards |= r.guard != first_guard;
  }
  std::map<std::string, int> x_values;
  for (const Row& r : rows) {
    if (r.method != "stale") x_values[r.x_max_text()] += 1;
  }
  several_x = x_values.size() > 1;  // x_max is meaningless for stale
  // An x_max sweep is plotted against the frames actually predicted (x), one line per method and RTT;
  // otherwise against the age of the visibility (p = x with x_max unlimited), one line per method.
  const auto label = [&](const Row& r) {
    return several_x ? r.method + " rtt " + fmt(0, r.rtt_ms) + " ms" : r.method;
  };
  const auto frames_x = [&](const Row& r) { return several_x ? r.frames_predicted : r.frames_behind; };

  SeriesSet ssim_s, flip_s, psnr_s, bits_s, resp_s, cost_s, points_s, rays_s;
  for (const Row& r : rows) {
    if (r.guard == first_guard) {
      ssim_s.at(label(r)).points.emplace_back(frames_x(r), r.ssim);
      if (r.has_flip) flip_s.at(label(r)).points.emplace_back(frames_x(r), r.flip);
      if (!r.psnr_inf) psnr_s.at(label(r)).points.emplace_back(frames_x(r), r.psnr);
      if (!several_x || r.x_max < 0 || r.method == "stale") {
        resp_s.at(r.method).points.emplace_back(r.rtt_ms, r.response_ms);
      }
    }
    if (r.method != "stale") bits_s.at(label(r) + " guard " + r.guard).points.emplace_back(frames_x(r), r.bit_error);
    if (r.rtt_ms == rows.front().rtt_ms) {
      cost_s.at("server (trace, per eye)").points.emplace_back(r.guard_px, r.server_ms);
    }
    points_s.at(r.method).points.emplace_back(r.frame_ms(), r.bit_error);
    rays_s.at(r.method).points.emplace_back(r.rays_per_pixel, r.visibility_error);
  }
  points_s.list.push_back(Series{"Pareto front", pareto_front(rows)});

  std::vector<std::pair<std::string, std::string>> figures;
  const auto add = [&](const std::string& caption, const std::string& file) {
    if (!file.empty()) figures.emplace_back(caption, file);
  };
  const std::string frames_label = several_x ? "frames predicted (x = min(x_max, p))"
                                             : "frames predicted (p: age of the visibility, x_max unlimited)";
  add("SSIM vs frames predicted", plot(dir, "ssim_vs_frames", "SSIM of the shaded luma", frames_label, "SSIM", ssim_s.list));
  add("FLIP vs frames predicted", plot(dir, "flip_vs_frames", "FLIP (LDR) of the shaded image", frames_label,
                                     "mean FLIP (0 = identical)", flip_s.list));
  add("PSNR vs frames predicted", plot(dir, "psnr_vs_frames", "PSNR of the shaded luma", frames_label, "PSNR (dB)", psnr_s.list));
  add("Bitwise visibility error vs frames predicted, per guard band",
      plot(dir, "bit_error_vs_frames", "wrong pixel-light bits / all", frames_label, "bit error", bits_s.list));
  add("Response time vs ping", plot(dir, "response_vs_ping", "pose sent -> visibility in use", "round trip (ms)",
                                    "response (ms)", resp_s.list));
  if (several_guards) {
    add("Trace time vs guard band (extra pixels per row)",
        plot(dir, "cost_vs_guard", "server trace time vs guard band", "guard band, extra pixels per row at this eye size",
             "ms per eye", cost_s.list));
  }
  add("Server rays per pixel vs visibility error (each point a setting; local traces none)",
      plot(dir, "rays_vs_visibility_error", "server rays vs visibility error",
           "server occlusion rays per surface pixel (all lights)", "mean |k shown - k exact|", rays_s.list, false));
  add("Run time vs error (Pareto front)",
      plot(dir, "pareto", "run time vs error", "client + server ms per frame (both eyes)", "bit error", points_s.list,
           false));

  std::ostringstream md;
  md << "# dhr-eval report\n\n";
  if (run.is_object()) {
    md << "Command: `" << run.value("command", "") << "`\n\n";
    md << "Scene `" << run.value("scene", "") << "`, trace `" << run.value("trace", "") << "` from "
       << fmt(1, num(run, "trace_start_s")) << " s, " << run.value("frames", 0) << " measured frames (after "
       << run.value("warmup_frames", 0) << " warm-up frames) at " << fmt(0, num(run, "frame_rate_hz")) << " Hz, eyes "
       << run.value("eye_width", 0) << "x" << run.value("eye_height", 0) << ", " << run.value("lights", 0)
       << " lights, jitter " << fmt(1, num(run, "jitter_ms")) << " ms, loss " << fmt(3, num(run, "loss"))
       << ", modelled server time " << fmt(1, num(run, "server_model_ms")) << " ms per frame"
       << ". Client: " << run.value("client_device", "") << "; tracer: " << run.value("tracer", "") << ". Wall time "
       << fmt(0, num(run, "wall_s")) << " s.\n\n";
  }
  md << "| method | rtt ms | x_max | guard | p | bit error | visibility error | SSIM | FLIP | PSNR dB | unknown | "
        "client ms | server ms | server rays/px | bytes/frame | response ms |\n";
  md << "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Row& r : rows) {
    md << "| " << r.method << " | " << fmt(0, r.rtt_ms) << " | " << r.x_max_text() << " | " << r.guard << " | "
       << fmt(2, r.frames_behind) << " | " << fmt(5, r.bit_error) << " | " << fmt(5, r.visibility_error) << " | "
       << fmt(4, r.ssim) << " | "
       << (r.has_flip ? fmt(4, r.flip) : std::string("-")) << " | "
       << (r.psnr_inf ? std::string("inf") : fmt(2, r.psnr)) << " | " << fmt(4, r.unknown_frac) << " | "
       << fmt(2, r.client_ms) << " | " << fmt(2, r.server_ms) << " | " << fmt(2, r.rays_per_pixel) << " | "
       << fmt(0, r.bytes_per_frame)
       << " | " << fmt(1, r.response_ms) << " |\n";
  }
  md << "\n";
  for (const auto& [caption, file] : figures) md << "![" << caption << "](" << file << ")\n\n";
  std::ofstream out(dir / "report.md");
  out << md.str();
  if (!out) {
    std::fprintf(stderr, "dhr-eval: %s: cannot write\n", (dir / "report.md").string().c_str());
    return 1;
  }
  std::printf("dhr-eval: wrote %s and %zu plots\n", (dir / "report.md").string().c_str(), figures.size());
  return 0;
}

}  // namespace dhr::eval
