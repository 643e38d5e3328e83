// Writes the fuzz targets' seed corpora: OUT_DIR/<target>/<seed name>, one directory per target
// (emptied first, since libFuzzer adds what it finds to the first corpus directory it is given).
//   dhr_fuzz_seeds OUT_DIR [TARGET...]      (default: every target)
#include "cli/exit_codes.hpp"
#include "cli/help_flag.hpp"
#include "fuzz_support.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (dhr::cli::asks_for_help(argc, argv)) {
    std::printf("usage: %s OUT_DIR [TARGET...]\nWrites each target's seeds to OUT_DIR/<target>/ (emptied first).\n",
                argv[0]);
    return dhr::exit_code::kOk;
  }
  // An option is never taken for a directory: an earlier `dhr_fuzz_seeds --help` wrote a corpus into ./--help.
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] == '-') {
      std::fprintf(stderr, "%s: unknown option '%s' (see --help)\n", argv[0], argv[i]);
      return dhr::exit_code::kUsage;
    }
  }
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR [TARGET...]\n", argv[0]);
    return dhr::exit_code::kUsage;
  }
  namespace fs = std::filesystem;
  std::vector<std::string> targets(argv + 2, argv + argc);
  if (targets.empty()) targets = dhr::fuzz::seed_targets();
  for (const std::string& target : targets) {
    const std::vector<dhr::fuzz::Seed> seeds = dhr::fuzz::seeds_for(target);
    if (seeds.empty()) {
      std::fprintf(stderr, "%s: unknown target '%s'\n", argv[0], target.c_str());
      return dhr::exit_code::kUsage;
    }
    const fs::path dir = fs::path(argv[1]) / target;
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    if (ec) {
      std::fprintf(stderr, "%s: cannot create %s: %s\n", argv[0], dir.string().c_str(), ec.message().c_str());
      return dhr::exit_code::kFailure;
    }
    for (const dhr::fuzz::Seed& seed : seeds) {
      std::ofstream out(dir / seed.name, std::ios::binary);
      out.write(reinterpret_cast<const char*>(seed.bytes.data()), static_cast<std::streamsize>(seed.bytes.size()));
      if (!out) {
        std::fprintf(stderr, "%s: cannot write %s\n", argv[0], (dir / seed.name).string().c_str());
        return dhr::exit_code::kFailure;
      }
    }
    std::printf("%s: %zu seeds in %s\n", target.c_str(), seeds.size(), dir.string().c_str());
  }
  return 0;
}
