#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace rpu::fp {

// A binary floating-point format: sign, `exponent_bits` of biased exponent and
// `fraction_bits` of stored fraction, laid out like IEEE 754-2019 §3.4 and held
// right-aligned in a uint32. The contract (rounding, flushing, NaN) is in
// docs/numbers.md; this type only knows the encoding.
struct Format {
  int exponent_bits;
  int fraction_bits;

  constexpr int width() const { return 1 + exponent_bits + fraction_bits; }
  // IEEE 754-2019 §3.3: bias = emax = 2^(E-1) - 1, emin = 1 - emax.
  constexpr int bias() const { return (1 << (exponent_bits - 1)) - 1; }
  constexpr int max_exponent() const { return bias(); }
  constexpr int min_exponent() const { return 1 - bias(); }

  constexpr std::uint32_t sign_mask() const { return std::uint32_t{1} << (width() - 1); }
  constexpr std::uint32_t fraction_mask() const { return (std::uint32_t{1} << fraction_bits) - 1; }
  constexpr std::uint32_t exponent_field_max() const { return (std::uint32_t{1} << exponent_bits) - 1; }
  constexpr std::uint32_t exponent_mask() const { return exponent_field_max() << fraction_bits; }
  constexpr std::uint32_t all_bits() const { return sign_mask() | exponent_mask() | fraction_mask(); }

  constexpr std::uint32_t sign_bit(bool negative) const { return negative ? sign_mask() : 0; }
  constexpr std::uint32_t zero(bool negative) const { return sign_bit(negative); }
  constexpr std::uint32_t infinity(bool negative) const { return sign_bit(negative) | exponent_mask(); }
  constexpr std::uint32_t max_finite(bool negative) const {
    return sign_bit(negative) | (exponent_mask() - (std::uint32_t{1} << fraction_bits)) | fraction_mask();
  }
  constexpr std::uint32_t min_normal(bool negative) const {
    return sign_bit(negative) | (std::uint32_t{1} << fraction_bits);
  }
  constexpr std::uint32_t one(bool negative) const {
    return sign_bit(negative) | (static_cast<std::uint32_t>(bias()) << fraction_bits);
  }
  // The one NaN every operation returns: sign 0, exponent all ones, fraction MSB set
  // (a quiet NaN in the IEEE 754-2019 §6.2.1 convention), rest zero.
  constexpr std::uint32_t canonical_nan() const {
    return exponent_mask() | (std::uint32_t{1} << (fraction_bits - 1));
  }

  constexpr std::uint32_t exponent_field(std::uint32_t bits) const {
    return (bits >> fraction_bits) & exponent_field_max();
  }
  constexpr bool is_negative(std::uint32_t bits) const { return (bits & sign_mask()) != 0; }
  constexpr bool is_nan(std::uint32_t bits) const {
    return exponent_field(bits) == exponent_field_max() && (bits & fraction_mask()) != 0;
  }
  constexpr bool is_inf(std::uint32_t bits) const {
    return exponent_field(bits) == exponent_field_max() && (bits & fraction_mask()) == 0;
  }
  // Zero or subnormal: both read as a signed zero (DAZ).
  constexpr bool is_zero_after_flush(std::uint32_t bits) const { return exponent_field(bits) == 0; }

  // "E8M23" style; format_by_name() accepts it back.
  std::string name() const;

  friend constexpr bool operator==(const Format&, const Format&) = default;
};

inline constexpr Format kFp32{8, 23};

// fp32 bits times 2^e: exact while the result is a normal number; a zero or subnormal
// input gives a signed zero (DAZ), a result below the normal range a signed zero (FTZ),
// one beyond it a signed infinity; infinities and NaNs pass unchanged. The traversal
// unit moves rays into kd space and hits back with it (docs/traversal.md §1, §6); the
// RTL's rtl/rpu_fp32_scale.sv is the same function.
constexpr std::uint32_t scale_fp32(std::uint32_t bits, int e) {
  const std::uint32_t sign = bits & 0x80000000u, field = (bits >> 23) & 0xffu;
  if (field == 0xffu) return bits;
  if (field == 0) return sign;
  const int exponent = static_cast<int>(field) + e;
  if (exponent >= 0xff) return sign | 0x7f800000u;
  if (exponent <= 0) return sign;
  return sign | (static_cast<std::uint32_t>(exponent) << 23) | (bits & 0x007fffffu);
}

// A format by spec name (rpu::spec::kFormats: "fp32", "rpu24", ...) or as "E<e>M<m>"
// with 2 <= e <= 8 and 1 <= m <= 23. Throws rpu::Error listing the known names.
Format format_by_name(std::string_view name);
// The name format_by_name takes for f: its spec name if it has one, else "E<e>M<m>".
std::string format_label(const Format& f);

}  // namespace rpu::fp
