#include "eval_compare.hpp"

#include "cli/exit_codes.hpp"

#include "compare_pictures.hpp"
#include "eval_render.hpp"
#include "eval_truth.hpp"
#include "image/png_writer.hpp"
#include "trace/embree/embree_tracer.hpp"
#include "log/log.hpp"
#include "metrics/image_metrics.hpp"
#include "scene/scene.hpp"
#include "scene/scene_hash.hpp"
#include "traces/shown_frame.hpp"
#include "vk/context.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <tuple>

namespace dhr::eval {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::string frame_name(const char* prefix, uint64_t frame) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%06llu.png", prefix, static_cast<unsigned long long>(frame));
  return name;
}

RgbImage rgb_from_rgba(const std::vector<uint8_t>& rgba, Extent size) {
  RgbImage out{size.width, size.height, std::vector<uint8_t>(rgba.size() / 4 * 3)};
  for (size_t i = 0, j = 0; i + 3 < rgba.size(); i += 4, j += 3) {
    out.rgb[j] = rgba[i];
    out.rgb[j + 1] = rgba[i + 1];
    out.rgb[j + 2] = rgba[i + 2];
  }
  return out;
}

std::vector<uint8_t> rgba_from_rgb(const RgbImage& image) {
  std::vector<uint8_t> out(image.rgb.size() / 3 * 4, 255);
  for (size_t i = 0, j = 0; i + 2 < image.rgb.size(); i += 3, j += 4) {
    out[j] = image.rgb[i];
    out[j + 1] = image.rgb[i + 1];
    out[j + 2] = image.rgb[i + 2];
  }
  return out;
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, fraction < 0.001 && fraction > 0.0 ? "%.3f %%" : "%.2f %%", 100.0 * fraction);
  return text;
}

// How old the visibility each eye used was: "visibility 1 frame old", "visibility 1 frame old (left), 2 (right)".
std::string visibility_words(const ShownFrame& f) {
  const auto age = [](const ShownEye& e) {
    if (!e.has_visibility) return std::string("none yet");
    return std::to_string(e.age) + (e.age == 1 ? " frame old" : " frames old") + (e.complete ? "" : ", rows missing");
  };
  const std::string left = age(f.eyes[0]), right = age(f.eyes[1]);
  if (!f.eyes[0].has_visibility && !f.eyes[1].has_visibility) return "no visibility from the server yet";
  return left == right ? "visibility " + left : "visibility " + left + " (left), " + right + " (right)";
}

class Comparer {
 public:
  Comparer(const CompareOptions& options, const Scene& scene)
      : options_(options), scene_(scene), scene_hash_(scene_content_hash(scene)) {
    vk::ContextOptions vk_options;
    vk_options.app_name = "dhr-eval";
    context_ = vk::Context::create(vk_options);
    server::TracerOptions tracer_options;
    tracer_options.threads = options.threads;
    tracer_ = std::make_unique<server::EmbreeTracer>(scene, tracer_options);
    lights_ = std::span(scene.lights).first(std::min<size_t>(scene.lights.size(), kMaxLights));
    sampling_.threads = options.threads;
    std::string font_error;
    face_ = TextFace::load(default_font_path(), &font_error);
    if (!face_) log::warn("dhr-eval compare: %s; the pictures carry no text (install fonts-dejavu-core)", font_error.c_str());
  }

  std::string device() const { return context_->info().name; }

  // Compares one saved frame; throws std::runtime_error with a one-line reason.
  Json compare(const ShownFrame& f) {
    // The Welcome's hash of what the server traced: another file (or dhr-server --lights) makes the exact
    // shading of --scene meaningless for this frame.
    if (f.scene_hash && *f.scene_hash != scene_hash_) {
      char text[96];
      std::snprintf(text, sizeof text, "the server traced another scene (hash %016llx; --scene has %016llx)",
                    static_cast<unsigned long long>(*f.scene_hash), static_cast<unsigned long long>(scene_hash_));
      throw std::runtime_error(text);
    }
    std::array<RgbImage, 2> shown;
    for (size_t e = 0; e < 2; ++e) {
      const std::string path = (fs::path(options_.shown_dir) / f.eyes[e].file).string();
      std::string error;
      auto image = read_png_rgb(path, &error);
      if (!image) throw std::runtime_error(error);
      if (image->width != f.eye_size.width || image->height != f.eye_size.height) {
        throw std::runtime_error(path + ": " + std::to_string(image->width) + "x" + std::to_string(image->height) +
                                 ", but the frame's eyes are " + std::to_string(f.eye_size.width) + "x" +
                                 std::to_string(f.eye_size.height));
      }
      shown[e] = std::move(*image);
    }
    const auto start = std::chrono::steady_clock::now();
    const GuardBand guard = f.traced ? f.traced->guard : GuardBand{};
    EyeRenderer& eye_renderer = renderer(f.eye_size, f.render_path == "forward");
    FramePose pose;
    pose.frame = f.frame;
    pose.views = {f.eyes[0].view, f.eyes[1].view};
    pose.scene_time_ns = f.scene_time_ns;
    const Truth truth = ground_truth(TruthScene{tracer_.get(), &scene_, lights_, eye_renderer.layout()}, sampling_,
                                     eye_renderer, f.eye_size, guard, pose);
    const double exact_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    std::array<RgbImage, 2> exact;
    std::array<EyeDifference, 2> diff;
    Json eyes = Json::array();
    uint64_t pixels = 0, differing = 0;
    for (size_t e = 0; e < 2; ++e) {
      exact[e] = rgb_from_rgba(truth.rgba[e], f.eye_size);
      diff[e] = difference(shown[e], exact[e], options_.tolerance);
      const std::optional<double> s =
          ssim(luma_from_rgba8(rgba_from_rgb(shown[e]), f.eye_size.width, f.eye_size.height), truth.luma[e]);
      const double n = static_cast<double>(diff[e].pixels);
      eyes.push_back(Json{{"file", f.eyes[e].file},
                          {"has_visibility", f.eyes[e].has_visibility},
                          {"age", f.eyes[e].age},
                          {"differing_frac", static_cast<double>(diff[e].differing()) / n},
                          {"too_lit_frac", static_cast<double>(diff[e].too_lit) / n},
                          {"too_dark_frac", static_cast<double>(diff[e].too_dark) / n},
                          {"ssim", s ? Json(*s) : Json(nullptr)}});
      pixels += diff[e].pixels;
      differing += diff[e].differing();
    }
    const double differing_frac = static_cast<double>(differing) / static_cast<double>(pixels);

    const std::string eyes_path = (fs::path(options_.out_dir) / frame_name("eyes", f.frame)).string();
    const std::string compare_path = (fs::path(options_.out_dir) / frame_name("compare", f.frame)).string();
    const std::string size = std::to_string(f.eye_size.width) + "x" + std::to_string(f.eye_size.height);
    write(eyes_path, eyes_picture(shown, face_.get(),
                                  "Frame " + std::to_string(f.frame) + " as shown: left and right eye, " + size +
                                      " each, " + visibility_words(f)));
    ComparisonText words;
    words.title = "Frame " + std::to_string(f.frame) + ": shown vs exact shading for the same pose";
    words.shown = "Shown: " + visibility_words(f) + ", warped to this pose (" + f.warp + " warp)";
    words.exact = "Exact: visibility ray-traced for this very pose (Embree), shaded by the client's pipeline";
    words.difference = "Difference: " + percent(differing_frac) + " of pixels (left " +
                       percent(static_cast<double>(diff[0].differing()) / static_cast<double>(diff[0].pixels)) +
                       ", right " +
                       percent(static_cast<double>(diff[1].differing()) / static_cast<double>(diff[1].pixels)) + ")";
    write(compare_path, comparison_picture(shown, exact, diff, face_.get(), words));
    const std::string strip_path = (fs::path(options_.out_dir) / frame_name("strip", f.frame)).string();
    write(strip_path, strip_picture(shown[0], exact[0], diff[0], face_.get(),
                                    "Frame " + std::to_string(f.frame) + ", left eye: " + visibility_words(f) + "; " +
                                        percent(static_cast<double>(diff[0].differing()) /
                                                static_cast<double>(diff[0].pixels)) +
                                        " of pixels differ from the exact shading"));

    Json line{{"frame", f.frame},
              {"eye_size", {f.eye_size.width, f.eye_size.height}},
              {"render_path", f.render_path},
              {"warp", f.warp},
              {"differing_frac", differing_frac},
              {"eyes", std::move(eyes)},
              {"exact_ms", exact_ms},
              {"eyes_picture", eyes_path},
              {"comparison_picture", compare_path},
              {"strip_picture", strip_path}};
    return line;
  }

 private:
  EyeRenderer& renderer(Extent size, bool forward) {
    auto& slot = renderers_[std::make_tuple(size.width, size.height, forward)];
    if (!slot) slot = std::make_unique<EyeRenderer>(*context_, scene_, size, render::ShadowMapSettings{}, forward);
    return *slot;
  }

  static void write(const std::string& path, const RgbImage& image) {
    if (auto error = write_png(path, image.width, image.height, 3, image.rgb)) throw std::runtime_error(*error);
  }

  const CompareOptions& options_;
  const Scene& scene_;
  uint64_t scene_hash_;
  std::unique_ptr<vk::Context> context_;
  std::unique_ptr<server::EmbreeTracer> tracer_;
  std::span<const SceneLight> lights_;  // the traced ones (at most kMaxLights)
  TruthSampling sampling_;
  std::unique_ptr<TextFace> face_;
  std::map<std::tuple<uint32_t, uint32_t, bool>, std::unique_ptr<EyeRenderer>> renderers_;
};

}  // namespace

int run_compare(const CompareOptions& given) {
  CompareOptions options = given;
  if (options.out_dir.empty()) options.out_dir = options.shown_dir;
  const std::string views_path = (fs::path(options.shown_dir) / kShownFramesFile).string();
  std::string error;
  const auto frames = read_shown_frames(views_path, &error);
  if (!frames) {
    const bool missing = !fs::exists(views_path);
    std::fprintf(stderr, "dhr-eval compare: %s%s\n", error.c_str(),
                 missing ? " (dhr-xrclient writes it next to its PNGs: --snapshot-dir or --offscreen)" : "");
    return exit_code::kUsage;
  }
  if (frames->empty()) {
    std::fprintf(stderr, "dhr-eval compare: %s: no saved frames\n", views_path.c_str());
    return exit_code::kUsage;
  }
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec || !fs::is_directory(options.out_dir)) {
    std::fprintf(stderr, "dhr-eval compare: %s: cannot create the output directory\n", options.out_dir.c_str());
    return exit_code::kFailure;
  }
  try {
    const SceneLoadResult loaded = load_scene(options.scene);
    if (!loaded) throw cli::InputError(loaded.error);
    Comparer comparer(options, *loaded.scene);
    uint64_t compared = 0, skipped = 0, failed = 0;
    double differing_sum = 0.0;
    for (size_t i = 0; i < frames->size(); ++i) {
      const ShownFrame& f = (*frames)[i];
      Json line;
      if (f.view != "shaded") {
        line = Json{{"frame", f.frame}, {"skipped", "the pictures show --view " + f.view + ", not the shaded image"}};
        ++skipped;
      } else {
        try {
          line = comparer.compare(f);
          ++compared;
          differing_sum += line["differing_frac"].get<double>();
          std::fprintf(stderr, "dhr-eval compare: frame %llu (%zu/%zu): %s of pixels differ from the exact shading\n",
                       static_cast<unsigned long long>(f.frame), i + 1, frames->size(),
                       percent(line["differing_frac"].get<double>()).c_str());
        } catch (const std::exception& e) {
          std::fprintf(stderr, "dhr-eval compare: frame %llu: %s\n", static_cast<unsigned long long>(f.frame), e.what());
          line = Json{{"frame", f.frame}, {"error", e.what()}};
          ++failed;
        }
      }
      std::printf("%s\n", line.dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
      std::fflush(stdout);
    }
    const Json summary{{"summary", true},
                       {"frames", frames->size()},
                       {"compared", compared},
                       {"skipped", skipped},
                       {"failed", failed},
                       {"differing_frac_mean", compared > 0 ? Json(differing_sum / static_cast<double>(compared))
                                                            : Json(nullptr)},
                       {"device", comparer.device()},
                       {"out", options.out_dir}};
    std::printf("%s\n", summary.dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
    return failed > 0 ? exit_code::kFailure : exit_code::kOk;
  } catch (const cli::InputError& e) {
    std::fprintf(stderr, "dhr-eval compare: %s\n", e.what());
    return exit_code::kUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dhr-eval compare: %s\n", e.what());
    return exit_code::kFailure;
  }
}

}  // namespace dhr::eval
