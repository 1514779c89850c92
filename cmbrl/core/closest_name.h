// "Did you mean" for error messages: the known name that a misspelt one most likely meant.
#pragma once

#include <algorithm>
#include <cctype>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cmbrl {

// Edits (insertions, deletions, substitutions, swaps of neighbours) between a and b, letters
// compared without case.
inline size_t NameDistance(std::string_view a, std::string_view b) {
  const auto same = [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) ==
           std::tolower(static_cast<unsigned char>(y));
  };
  // Rows i-2, i-1 and i of the table over prefixes of a and b.
  std::vector<size_t> before(b.size() + 1), last(b.size() + 1), row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) last[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitution = last[j - 1] + (same(a[i - 1], b[j - 1]) ? 0 : 1);
      row[j] = std::min({last[j] + 1, row[j - 1] + 1, substitution});
      if (i > 1 && j > 1 && same(a[i - 1], b[j - 2]) && same(a[i - 2], b[j - 1])) {
        row[j] = std::min(row[j], before[j - 2] + 1);
      }
    }
    std::swap(before, last);
    std::swap(last, row);
  }
  return last[b.size()];
}

// The one candidate nearest to `name`, when it is near enough to be a slip (at most a third of
// the name's letters edited, at least one) and no other candidate is as near; else none.
template <typename Names>
std::optional<std::string> ClosestName(std::string_view name, const Names& candidates) {
  const size_t allowed = std::max<size_t>(1, name.size() / 3);
  std::optional<std::string> best;
  size_t best_distance = allowed + 1;
  bool tie = false;
  for (const auto& candidate : candidates) {
    const std::string_view text(candidate);
    if (text == name) continue;
    const size_t distance = NameDistance(name, text);
    if (distance < best_distance) {
      best = std::string(text);
      best_distance = distance;
      tie = false;
    } else if (distance == best_distance) {
      tie = true;
    }
  }
  if (tie) return std::nullopt;
  return best;
}

// " (did you mean 'x'?)" for the closest candidate, or "" when none is close; `prefix` goes
// before the candidate's name in the message (a key's section: "planning.").
template <typename Names>
std::string DidYouMean(std::string_view name, const Names& candidates,
                       std::string_view prefix = "") {
  const std::optional<std::string> closest = ClosestName(name, candidates);
  return closest ? " (did you mean '" + std::string(prefix) + *closest + "'?)" : "";
}

}  // namespace cmbrl
