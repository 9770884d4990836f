#pragma once

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

namespace rpu {

// Levenshtein distance: insertions, deletions and substitutions, one each.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// " (did you mean 'x'?)" for the closest candidate within two edits (and not all of
// it changed), else "". Names beyond 64 characters get none: nobody mistypes those,
// and the distance is quadratic in the length.
inline std::string did_you_mean(std::string_view wrong, const std::vector<std::string_view>& candidates) {
  if (wrong.size() > 64) return "";
  std::string_view best;
  std::size_t best_distance = 3;
  for (const std::string_view c : candidates) {
    const std::size_t d = edit_distance(wrong, c);
    if (d < best_distance && d < std::max(wrong.size(), c.size())) {
      best = c;
      best_distance = d;
    }
  }
  return best.empty() ? std::string() : " (did you mean '" + std::string(best) + "'?)";
}

}  // namespace rpu
