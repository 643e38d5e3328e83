// Command-line options for network impairment, shared by dhr-server, dhr-xrclient and dhr-eval:
//   --net-delay MS  --net-jitter MS  --net-jitter-dist uniform|normal  --net-loss FRACTION
//   --net-burst-loss P_GOOD_TO_BAD,P_BAD_TO_GOOD[,LOSS_IN_BAD]  --net-reorder FRACTION
//   --net-reorder-delay MS  --net-duplicate FRACTION  --net-seed N
// Each option checks its own range, so after CLI::App::parse the params are valid (validate() agrees).
#pragma once
#include "net/impairment.hpp"

#include <string>
#include <string_view>

namespace CLI {
class App;
}

namespace dhr::net {

// Registers the options (help group "Network impairment") writing into `params`, which must outlive
// the parse. Defaults are whatever `params` holds.
void add_impairment_options(CLI::App& app, ImpairmentParams& params);

// "P_GOOD_TO_BAD,P_BAD_TO_GOOD" or "P_GOOD_TO_BAD,P_BAD_TO_GOOD,LOSS_IN_BAD" into the burst_* fields.
// False (params untouched, reason in *out_error) on malformed text or values out of range.
bool parse_burst_loss(std::string_view text, ImpairmentParams& params, std::string* out_error = nullptr);

}  // namespace dhr::net
