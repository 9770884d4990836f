#include "fp/format.hpp"

#include <charconv>

#include "common/error.hpp"
#include "rpu/spec.hpp"

namespace rpu::fp {

std::string Format::name() const {
  std::string text = std::to_string(fraction_bits);
  text.insert(0, 1, 'M');
  text.insert(0, std::to_string(exponent_bits));
  text.insert(0, 1, 'E');
  return text;
}

namespace {

// Parses a decimal number spanning all of `text`; -1 if it is not one.
int parse_count(std::string_view text) {
  int value = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size()) return -1;
  return value;
}

}  // namespace

Format format_by_name(std::string_view name) {
  for (const spec::FormatSpec& f : spec::kFormats) {
    if (f.name == name) return Format{f.exponent_bits, f.fraction_bits};
  }
  if (name.size() >= 4 && (name[0] == 'E' || name[0] == 'e')) {
    const std::size_t m = name.find_first_of("Mm");
    if (m != std::string_view::npos) {
      const int e_bits = parse_count(name.substr(1, m - 1));
      const int m_bits = parse_count(name.substr(m + 1));
      // The soft arithmetic holds a significand and guard bits in 128 bits and an
      // exponent field in 8 bits; spec/gen.py enforces the same limits.
      if (e_bits >= 2 && e_bits <= 8 && m_bits >= 1 && m_bits <= 23) return Format{e_bits, m_bits};
    }
  }
  std::string message = "unknown number format '";
  message.append(name).append("': use one of ");
  for (const spec::FormatSpec& f : spec::kFormats) {
    if (&f != &spec::kFormats.front()) message.append(", ");
    message.append(f.name);
  }
  message.append(" (spec/formats.toml) or E<e>M<m> with 2 <= e <= 8 and 1 <= m <= 23");
  throw Error(message);
}

std::string format_label(const Format& f) {
  for (const spec::FormatSpec& s : spec::kFormats) {
    if (s.exponent_bits == f.exponent_bits && s.fraction_bits == f.fraction_bits) return std::string(s.name);
  }
  return f.name();
}

}  // namespace rpu::fp
