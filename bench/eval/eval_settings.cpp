#include "eval_settings.hpp"

#include "plan/shipped_defaults.hpp"
#include "session/shipped_defaults.hpp"
#include "render/warp_edges.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <array>
#include <utility>

namespace dhr::eval {

namespace {

constexpr std::array<std::pair<Ingredient, const char*>, 12> kIngredients = {{
    {kIngredientBilinear, "bilinear"},
    {kIngredientDepthTest, "depth"},
    {kIngredientOtherEye, "other-eye"},
    {kIngredientShadowFill, "shadow-fill"},
    {kIngredientShadowEdges, "shadow-edges"},
    {kIngredientShadowFirst, "shadow-first"},
    {kIngredientPrediction, "pred"},
    {kIngredientAdaptiveFov, "adaptive-fov"},
    {kIngredientOlderBuffer, "older"},
    {kIngredientNeighbour, "neighbour"},
    {kIngredientMotion, "motion"},
    {kIngredientSoftRefine, "soft-refine"},
}};

}  // namespace

const char* method_name(Method method) {
  switch (method) {
    case Method::kStale: return "stale";
    case Method::kPaper: return "paper";
    case Method::kPaperPred: return "paper+pred";
    case Method::kLocal: return "local";
    case Method::kFull: return "full";
  }
  return "unknown";
}

MethodSpec shipped_method(bool soft_scene) {
  MethodSpec spec;
  spec.shipped = true;
  const client::WarpChoice warp = client::resolve_warp(client::shipped::kWarp, soft_scene);
  if (warp != client::WarpChoice::kPaper) {
    spec.method = Method::kFull;
    if (!server::shipped::kPredict) spec.without |= kIngredientPrediction;
    if (!server::shipped::kAdaptiveFov) spec.without |= kIngredientAdaptiveFov;
    // server_edges_depth(): full without the ingredients that decide before the server's bits or read other
    // buffers; edges (server_edges()) also without the depth test.
    if (warp == client::WarpChoice::kEdges || warp == client::WarpChoice::kEdgesDepth) {
      spec.without |= kIngredientShadowFirst | kIngredientOtherEye | kIngredientOlderBuffer | kIngredientNeighbour;
    }
    if (warp == client::WarpChoice::kEdges) spec.without |= kIngredientDepthTest;
    if ((spec.without & kIngredientDepthTest) == 0) {
      spec.depth_scale = client::shipped::kDepthScale;
      spec.depth_splat = client::shipped::kTracedDepth == client::TracedDepth::kSplat;
    }
  } else {
    spec.method = server::shipped::kPredict ? Method::kPaperPred : Method::kPaper;
  }
  return spec;
}

std::string method_name(const MethodSpec& spec) {
  if (spec.shipped) return "default";
  std::string name = method_name(spec.method);
  if (spec.method != Method::kFull) return name;
  for (const auto& [bit, text] : kIngredients) {
    if ((spec.without & bit) != 0) name += std::string("-no-") + text;
  }
  if (spec.depth_scale > 1) name += "-depth-scale-" + std::to_string(spec.depth_scale);
  if (spec.depth_splat) name += "-depth-splat";
  if (spec.edge_band != client::shipped::kEdgeBand) name += "-edge-band-" + std::to_string(spec.edge_band);
  return name;
}

std::optional<MethodSpec> parse_method(const std::string& text) {
  if (text == "default") return shipped_method(false);
  for (const Method m : {Method::kStale, Method::kPaper, Method::kPaperPred, Method::kLocal, Method::kFull}) {
    if (text == method_name(m)) return MethodSpec{m, 0};
  }
  const std::string prefix = "full";
  if (text.rfind(prefix, 0) != 0) return std::nullopt;
  MethodSpec spec{Method::kFull, 0};
  std::string rest = text.substr(prefix.size());
  const std::string band_item = "-edge-band-";
  const size_t band_at = rest.rfind(band_item);
  if (band_at != std::string::npos) {
    const std::string digits = rest.substr(band_at + band_item.size());
    if (digits.size() != 1 || digits.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
    spec.edge_band = static_cast<uint32_t>(std::stoul(digits));
    if (spec.edge_band > render::kMaxEdgeBand) return std::nullopt;
    rest = rest.substr(0, band_at);
  }
  const std::string splat_item = "-depth-splat";
  if (rest.size() >= splat_item.size() &&
      rest.compare(rest.size() - splat_item.size(), splat_item.size(), splat_item) == 0) {
    spec.depth_splat = true;
    rest = rest.substr(0, rest.size() - splat_item.size());
  }
  const std::string scale_item = "-depth-scale-";
  const size_t scale_at = rest.rfind(scale_item);
  if (scale_at != std::string::npos) {
    const std::string digits = rest.substr(scale_at + scale_item.size());
    if (digits.empty() || digits.size() > 2 || digits.find_first_not_of("0123456789") != std::string::npos) {
      return std::nullopt;
    }
    spec.depth_scale = static_cast<uint32_t>(std::stoul(digits));
    if (spec.depth_scale < 2 || spec.depth_scale > 16) return std::nullopt;
    rest = rest.substr(0, scale_at);
  }
  while (!rest.empty()) {
    bool matched = false;
    for (const auto& [bit, name] : kIngredients) {
      const std::string item = std::string("-no-") + name;
      if (rest.rfind(item, 0) == 0 && (rest.size() == item.size() || rest[item.size()] == '-')) {
        if ((spec.without & bit) != 0) return std::nullopt;
        spec.without |= bit;
        rest = rest.substr(item.size());
        matched = true;
        break;
      }
    }
    if (!matched) return std::nullopt;
  }
  if ((spec.depth_scale > 1 || spec.depth_splat) && (spec.without & kIngredientDepthTest) != 0) return std::nullopt;
  return spec;
}

MethodSpec for_scene(const MethodSpec& spec, bool soft_scene) {
  return spec.shipped ? shipped_method(soft_scene) : spec;
}

bool server_predicts(const MethodSpec& spec) {
  if (spec.shipped) return server::shipped::kPredict;
  return spec.method == Method::kPaperPred ||
         (spec.method == Method::kFull && (spec.without & kIngredientPrediction) == 0);
}

bool server_adapts_fov(const MethodSpec& spec) {
  if (spec.shipped) return server::shipped::kAdaptiveFov;
  return spec.method == Method::kFull && (spec.without & kIngredientAdaptiveFov) == 0;
}

bool uses_server_visibility(const MethodSpec& spec) { return spec.method != Method::kLocal; }

render::WarpSettings warp_settings(const MethodSpec& spec, const RunOptions& options) {
  render::WarpSettings s;
  s.plane_tolerance_rel = options.plane_tolerance_rel;
  s.plane_tolerance_abs = options.plane_tolerance_abs;
  if (spec.method == Method::kLocal) {
    s.shadow_fill = true;
    return s;
  }
  if (spec.shipped && client::shipped::kWarp == client::WarpChoice::kPaper) return s;  // the paper's warp
  if (spec.method != Method::kFull) return s;
  s.bilinear = (spec.without & kIngredientBilinear) == 0;
  s.depth_test = (spec.without & kIngredientDepthTest) == 0;
  s.other_eye = (spec.without & kIngredientOtherEye) == 0;
  s.shadow_fill = (spec.without & kIngredientShadowFill) == 0;
  s.shadow_edges = (spec.without & kIngredientShadowEdges) == 0;
  s.shadow_first = (spec.without & kIngredientShadowFirst) == 0;
  s.older_buffer = (spec.without & kIngredientOlderBuffer) == 0;
  s.neighbour_fill = (spec.without & kIngredientNeighbour) == 0;
  s.motion = (spec.without & kIngredientMotion) == 0;
  s.soft_refine = (spec.without & kIngredientSoftRefine) == 0;
  s.depth_scale = spec.depth_scale;
  s.depth_splat = spec.depth_splat;
  s.edge_band = spec.edge_band;
  return s;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const size_t end = comma == std::string::npos ? text.size() : comma;
    out.push_back(text.substr(start, end - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

namespace {

bool fail(std::string* out_error, const std::string& message) {
  if (out_error) *out_error = message;
  return false;
}

bool parse_double(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(s.c_str(), &end);
  return errno == 0 && end == s.c_str() + s.size() && std::isfinite(out);
}

bool parse_uint(const std::string& s, uint32_t& out) {
  if (s.empty() || s.size() > 9) return false;
  for (const char c : s) {
    if (c < '0' || c > '9') return false;
  }
  out = static_cast<uint32_t>(std::strtoul(s.c_str(), nullptr, 10));
  return true;
}

}  // namespace

std::optional<Extent> parse_size(const std::string& text) {
  const size_t x = text.find('x');
  uint32_t w = 0, h = 0;
  if (x == std::string::npos || !parse_uint(text.substr(0, x), w) || !parse_uint(text.substr(x + 1), h)) {
    return std::nullopt;
  }
  return Extent{w, h};
}

std::optional<std::vector<double>> parse_rtt_list(const std::string& text, std::string* out_error) {
  std::vector<double> out;
  for (const std::string& item : split_list(text)) {
    double v = 0.0;
    if (!parse_double(item, v) || v < 0.0 || v > 10000.0) {
      fail(out_error, "--rtt-ms: expected milliseconds in [0, 10000], got '" + item + "'");
      return std::nullopt;
    }
    out.push_back(v);
  }
  return out;
}

std::optional<std::vector<int>> parse_x_max_list(const std::string& text, std::string* out_error) {
  std::vector<int> out;
  for (const std::string& item : split_list(text)) {
    uint32_t v = 0;
    if (item == "all") {
      out.push_back(-1);
    } else if (parse_uint(item, v) && v <= 1000) {
      out.push_back(static_cast<int>(v));
    } else {
      fail(out_error, "--x-max: expected a frame count 0..1000 or 'all', got '" + item + "'");
      return std::nullopt;
    }
  }
  return out;
}

std::optional<std::vector<std::string>> parse_guard_list(const std::string& text, std::string* out_error) {
  std::vector<std::string> out;
  for (const std::string& item : split_list(text)) {
    const std::optional<Extent> e = parse_size(item);
    if (item != "0" && (!e || e->width > 1920 || e->height > 1080 || !guard_band_from_total(e->width, e->height))) {
      fail(out_error, "--guard: expected 0 or WxH pixels at 1920x1080, both sides together, even (e.g. 64x36), got '" +
                          item + "'");
      return std::nullopt;
    }
    out.push_back(item);
  }
  return out;
}

std::optional<std::vector<MethodSpec>> parse_method_list(const std::string& text, std::string* out_error) {
  std::vector<MethodSpec> out;
  for (const std::string& item : split_list(text)) {
    const std::optional<MethodSpec> m = parse_method(item);
    if (!m) {
      std::string names;  // the ingredients, from the one table parse_method reads
      for (const auto& [bit, name] : kIngredients) names += (names.empty() ? "" : ", ") + std::string(name);
      fail(out_error, "--method: expected default, stale, paper, paper+pred, local, full or full-no-<ingredient>... "
                      "(" + names + "), then optionally -depth-scale-N (2-16), -depth-splat and -edge-band-N (0-8), "
                      "got '" + item + "'");
      return std::nullopt;
    }
    out.push_back(*m);
  }
  return out;
}

std::string setting_label(const Setting& setting) {
  char rtt[32];
  std::snprintf(rtt, sizeof rtt, "%g", setting.rtt_ms);
  return std::string(method_name(setting.method)) + " rtt=" + rtt + "ms x_max=" +
         (setting.x_max < 0 ? std::string("all") : std::to_string(setting.x_max)) + " guard=" + setting.guard;
}

GuardBand guard_for_eye(const std::string& label, Extent eye) {
  const std::optional<Extent> e = parse_size(label);
  const std::optional<GuardBand> per_side = e ? guard_band_from_total(e->width, e->height) : std::nullopt;
  if (!per_side) return GuardBand{};
  return scale_guard_band(*per_side, Extent{1920, 1080}, eye);
}

std::vector<Setting> expand_settings(const RunOptions& options) {
  std::vector<Setting> out;
  for (const std::string& guard : options.guard) {
    for (const double rtt : options.rtt_ms) {
      for (const MethodSpec& method : options.methods) {
        if (method.shipped) {  // the client's own schedule and guard band, whatever the lists say
          if (guard != options.guard.front()) continue;
          const int x_max =
              client::shipped::kSchedule == client::Schedule::kNewest ? -1 : static_cast<int>(client::shipped::kXMax);
          out.push_back(Setting{method, rtt, x_max, kShippedGuardLabel, client::shipped::guard_band(options.eye)});
          continue;
        }
        if (method.method == Method::kStale || method.method == Method::kLocal) {
          out.push_back(Setting{method, rtt, -1, guard, guard_for_eye(guard, options.eye)});
          continue;
        }
        for (const int x_max : options.x_max) {
          out.push_back(Setting{method, rtt, x_max, guard, guard_for_eye(guard, options.eye)});
        }
      }
    }
  }
  return out;
}

}  // namespace dhr::eval
