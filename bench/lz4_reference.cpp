#include "lz4_reference.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>

namespace dhr::bench {
namespace {

// Output (stdout and stderr) and exit status of a shell command.
int run_command(const std::string& command, std::string& out) {
  out.clear();
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  char buffer[4096];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  const int status = ::pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool write_temp(const std::vector<uint8_t>& bytes, std::string& out_path) {
  char path[] = "/tmp/dhr-codec-bench-XXXXXX";
  const int fd = ::mkstemp(path);
  if (fd < 0) return false;
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t w = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (w <= 0) break;
    done += static_cast<size_t>(w);
  }
  ::close(fd);
  out_path = path;
  return done == bytes.size();
}

}  // namespace

bool parse_lz4_bench_output(const std::string& output, Lz4CliRun& out) {
  // lz4 redraws its progress line with '\r'; the last line carrying two MB/s figures is the result.
  bool found = false;
  size_t start = 0;
  while (start < output.size()) {
    size_t end = output.find_first_of("\r\n", start);
    if (end == std::string::npos) end = output.size();
    const std::string line = output.substr(start, end - start);
    start = end + 1;
    const size_t colon = line.find(':');
    if (colon == std::string::npos || line.find("->") == std::string::npos) continue;
    unsigned long long in = 0, compressed = 0;
    double ratio = 0.0, c = 0.0, d = 0.0;
    if (std::sscanf(line.c_str() + colon + 1, " %llu -> %llu (%lf),%lf MB/s ,%lf MB/s", &in, &compressed, &ratio, &c,
                    &d) == 5) {
      out.input_bytes = static_cast<size_t>(in);
      out.compressed_bytes = static_cast<size_t>(compressed);
      out.compress_mb_s = c;
      out.decompress_mb_s = d;
      found = true;
    }
  }
  return found;
}

Lz4CliResult run_lz4_cli(const std::vector<const std::vector<uint8_t>*>& buffers, int seconds) {
  Lz4CliResult result;
  if (seconds < 1) seconds = 1;
  result.command = "lz4 -b1 -i" + std::to_string(seconds) + " FILE";
  std::string out;
  const int status = run_command("lz4 -V", out);
  if (status != 0) {
    result.error = status == 127 ? "lz4 not found (Debian package lz4)" : "lz4 -V failed: " + out;
    return result;
  }
  result.version = out.substr(0, out.find_first_of("\r\n"));
  for (const std::vector<uint8_t>* bytes : buffers) {
    std::string path;
    if (!write_temp(*bytes, path)) {
      result.error = "cannot write a temporary file in /tmp";
      return result;
    }
    const int rc = run_command("lz4 -b1 -i" + std::to_string(seconds) + " " + path, out);
    ::unlink(path.c_str());
    Lz4CliRun run;
    if (rc != 0 || !parse_lz4_bench_output(out, run)) {
      result.error = "could not parse `lz4 -b` output: " + out.substr(0, 200);
      result.runs.clear();
      return result;
    }
    result.runs.push_back(run);
  }
  result.available = true;
  return result;
}

}  // namespace dhr::bench
