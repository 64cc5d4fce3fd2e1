#pragma once
// Checks on the numbers both tools take on the command line. A threshold, weight or scale must
// be a finite number (CLI11 parses "nan" and "inf" as doubles, and "-1" into an unsigned option
// as its largest value), and where the option says so, above or at zero; the message says that
// in words, not as a range to the last representable double.
#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

namespace lego::app {

enum class Sign { Any, NonNegative, Positive };

inline CLI::Validator finite_number(Sign sign = Sign::Any) {
  const char* words = sign == Sign::Positive      ? "a finite number above 0"
                      : sign == Sign::NonNegative ? "a finite number, 0 or more"
                                                  : "a finite number";
  return CLI::Validator(
      [sign, words](std::string& text) -> std::string {
        double v = 0;
        size_t used = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        const bool ok = used == text.size() && !text.empty() && std::isfinite(v) &&
                        (sign == Sign::Any || (sign == Sign::NonNegative ? v >= 0 : v > 0));
        return ok ? std::string() : "'" + text + "' is not " + words;
      },
      words);
}

}  // namespace lego::app
