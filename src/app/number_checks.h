#pragma once
// Checks on the numbers both tools take on the command line. A threshold, weight or scale must
// be a finite number (CLI11 parses "nan" and "inf" as doubles, and "-1" into an unsigned option
// as its largest value), and where the option says so, above or at zero; the message says that
// in words, not as a range to the last representable double.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

namespace lego::app {

enum class Sign { Any, NonNegative, Positive };

// With `at_most`, no more than that either.
inline CLI::Validator finite_number(Sign sign = Sign::Any, double at_most = INFINITY) {
  std::string words = sign == Sign::Positive      ? "a finite number above 0"
                      : sign == Sign::NonNegative ? "a finite number, 0 or more"
                                                  : "a finite number";
  if (std::isfinite(at_most)) words += fmt::format(", at most {:.0f}", at_most);
  return CLI::Validator(
      [sign, words, at_most](std::string& text) -> std::string {
        double v = 0;
        size_t used = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        const bool ok = used == text.size() && !text.empty() && std::isfinite(v) && v <= at_most &&
                        (sign == Sign::Any || (sign == Sign::NonNegative ? v >= 0 : v > 0));
        return ok ? std::string() : "'" + text + "' is not " + words;
      },
      words);
}

// A C_M threshold (--min-cm, gf): finite and below T, the most C_M can be (a model that pulls on
// no knob has C_M = T), so that a threshold no model can exceed is a usage error, not a verdict.
inline CLI::Validator cm_threshold(double t_gf) {
  const std::string words = fmt::format(
      "a finite number below {} (T: no model's C_M exceeds a knob's friction "
      "capacity, which it has when no knob is pulled)",
      t_gf);
  return CLI::Validator(
      [t_gf, words](std::string& text) -> std::string {
        std::string checked = text;
        if (std::string why = finite_number()(checked); !why.empty()) return why;
        return std::stod(text) < t_gf ? std::string() : "'" + text + "' is not " + words;
      },
      words);
}

}  // namespace lego::app
