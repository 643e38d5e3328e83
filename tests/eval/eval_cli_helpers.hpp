// dhr-eval's command line as the CLI tests run it (eval_cli_test.cpp, eval_methods_test.cpp): the shipped scene and
// trace, one run of the executable with its exit code and output, a fresh temporary folder, results.json by setting.
#pragma once
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace dhr::eval_test {

namespace fs = std::filesystem;
using nlohmann::json;

inline const std::string kScene = std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf";
inline const std::string kTrace = std::string(DHR_SOURCE_DIR) + "/assets/traces/synthetic_6dof.csv";

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout + stderr
};

inline CliRun run_cli(const std::string& args) {
  const std::string command = std::string(DHR_EVAL_EXE) + " " + args + " 2>&1";
  CliRun r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// `dhr-eval run` on `scene` and the shipped trace from 1 s, 64x48 eyes, no progress, results in `out`; `rest`:
// the frames, round trips, methods and anything else, each with a leading space.
inline CliRun run_small(const fs::path& out, const std::string& rest, const std::string& scene = kScene) {
  return run_cli("run --scene " + scene + " --trace " + kTrace + " --out " + out.string() +
                 " --trace-start 1.0 --eye-size 64x48 --no-progress" + rest);
}

inline fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("dhr_eval_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

inline json read_results(const fs::path& dir) {
  std::ifstream file(dir / "results.json");
  return json::parse(file);
}

// results keyed "method@rtt".
inline std::map<std::string, json> by_setting(const json& results) {
  std::map<std::string, json> out;
  for (const json& r : results) out[r["method"].get<std::string>() + "@" + std::to_string(r["rtt_ms"].get<int>())] = r;
  return out;
}

}  // namespace dhr::eval_test
