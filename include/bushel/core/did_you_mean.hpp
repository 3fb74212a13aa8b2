#pragma once
// Suggestions for misspelt names (template names, scenario keys, units).

#include <span>
#include <string>
#include <string_view>

namespace bushel {

/// Levenshtein edit distance between two strings (insert, delete, substitute: cost 1 each).
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `word` when it is close enough to be a likely typo (distance at
/// most a third of the word's length, and at least 1); empty otherwise.
std::string closest_match(std::string_view word, std::span<const std::string> candidates);

/// " (did you mean 'x'?)" or "" -- ready to append to an error message.
std::string did_you_mean(std::string_view word, std::span<const std::string> candidates);

}  // namespace bushel
