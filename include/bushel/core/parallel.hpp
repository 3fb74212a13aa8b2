#pragma once
// Below this many items a loop runs on one thread: forking and joining a team costs more
// than the work, and tiny scenes (verification, tests running side by side) would spend
// their time in barriers. Used as `#pragma omp parallel for if (n > parallel_threshold)`.

#include <cstddef>

namespace bushel {

inline constexpr std::ptrdiff_t parallel_threshold = 2048;

}  // namespace bushel
