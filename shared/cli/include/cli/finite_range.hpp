// A CLI11 check for numeric options: the value must be a finite number within [min, max]. CLI::Range alone
// lets "nan" through (every comparison with NaN is false), and a NaN option would reach the casts to integer
// nanoseconds (undefined behaviour) or the math. Use it instead of CLI::Range for every numeric option.
#pragma once
#include <CLI/CLI.hpp>

#include <cmath>
#include <sstream>
#include <string>

namespace dhr::cli {

class FiniteRange : public CLI::Validator {
 public:
  template <typename T>
  FiniteRange(T min, T max) : CLI::Validator(check(static_cast<double>(min), static_cast<double>(max)), describe(min, max)) {}

 private:
  template <typename T>
  static std::string describe(T min, T max) {
    std::ostringstream out;
    out << "[" << min << " - " << max << "]";
    return out.str();
  }
  static std::function<std::string(std::string&)> check(double min, double max) {
    return [min, max](std::string& text) -> std::string {
      double value = 0.0;
      if (!CLI::detail::lexical_cast(text, value)) return "'" + text + "' is not a number";
      if (!std::isfinite(value)) return "'" + text + "' is not a finite number";
      if (value < min || value > max) return "value " + text + " not in range " + describe(min, max);
      return {};
    };
  }
};

}  // namespace dhr::cli
