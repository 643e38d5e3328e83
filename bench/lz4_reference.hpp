// The reference next to the codec numbers: Debian's lz4 command-line tool benchmarking the same raw
// bytes (`lz4 -b1 -i<seconds> FILE`, each buffer written to a temporary file), its output parsed.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dhr::bench {

struct Lz4CliRun {
  size_t input_bytes = 0;
  size_t compressed_bytes = 0;
  double compress_mb_s = 0.0;    // as lz4 prints it (MB = 1e6 bytes)
  double decompress_mb_s = 0.0;
};

struct Lz4CliResult {
  bool available = false;   // the lz4 tool ran and its output was understood
  std::string version;      // first line of `lz4 -V`
  std::string command;      // the command line, with FILE standing for the temporary file
  std::string error;        // why not available
  std::vector<Lz4CliRun> runs;  // one per buffer
};

// Runs `lz4 -b1 -i<seconds>` on each buffer's bytes. Never throws; missing tool -> available = false.
Lz4CliResult run_lz4_cli(const std::vector<const std::vector<uint8_t>*>& buffers, int seconds);

// Parses the final result line of `lz4 -b` output ("... : 2214144 -> 81234 (27.26),3456.7 MB/s ,9876.5 MB/s");
// false when there is none.
bool parse_lz4_bench_output(const std::string& output, Lz4CliRun& out);

}  // namespace dhr::bench
