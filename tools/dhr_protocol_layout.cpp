// dhr-protocol-layout: the wire layout from the protocol's one field list (protocol/wire_layout.hpp), as
// docs/protocol.md's tables or as tools/wireshark/dhr.lua's layout section, or rewrites that section.
#include "cli/exit_codes.hpp"
#include "protocol/protocol_layout.hpp"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace {

constexpr const char* kUsage =
    "Usage: dhr-protocol-layout [--markdown | --lua | --update-wireshark DHR_LUA]\n"
    "  --markdown (default)      the byte tables, in docs/protocol.md's form\n"
    "  --lua                     the layout section of the Wireshark dissector\n"
    "  --update-wireshark FILE   rewrite FILE's section from '-- BEGIN LAYOUT' to '-- END LAYOUT'\n";

// Replaces the lines from the one starting with kLuaLayoutBegin to the one starting with kLuaLayoutEnd.
int update_wireshark(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::cerr << path << ": cannot read\n";
    return dhr::exit_code::kUsage;
  }
  std::ostringstream before, after;
  std::string line;
  int state = 0;  // 0 before the section, 1 inside, 2 after
  while (std::getline(in, line)) {
    if (state == 0 && line.starts_with(dhr::kLuaLayoutBegin)) {
      state = 1;
    } else if (state == 1) {
      if (line.starts_with(dhr::kLuaLayoutEnd)) state = 2;
    } else {
      (state == 0 ? before : after) << line << '\n';
    }
  }
  if (state != 2) {
    std::cerr << path << ": no '" << dhr::kLuaLayoutBegin << "' ... '" << dhr::kLuaLayoutEnd << "' lines\n";
    return dhr::exit_code::kUsage;
  }
  const std::string text = before.str() + dhr::layout_lua(dhr::protocol_layout()) + after.str();
  std::ofstream out(path, std::ios::trunc);
  if (!(out << text)) {
    std::cerr << path << ": cannot write\n";
    return dhr::exit_code::kFailure;
  }
  std::cout << path << ": layout section written\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "--markdown";
  if (argc == 3 && mode == "--update-wireshark") return update_wireshark(argv[2]);
  if (argc > 2) {
    std::cerr << kUsage;
    return dhr::exit_code::kUsage;
  }
  if (mode == "--markdown") {
    std::cout << dhr::layout_markdown(dhr::protocol_layout());
  } else if (mode == "--lua") {
    std::cout << dhr::layout_lua(dhr::protocol_layout());
  } else if (mode == "--help" || mode == "-h") {
    std::cout << kUsage;
  } else {
    std::cerr << kUsage;
    return dhr::exit_code::kUsage;
  }
  return 0;
}
