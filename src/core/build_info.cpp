#include "bushel/core/build_info.hpp"

#include <fmt/format.h>

namespace bushel {

std::string build_description(const BuildInfo& info) {
  // 12 hex digits name a commit unambiguously in any repository of this size
  return fmt::format("{} (commit {}{})", info.version, info.commit.substr(0, 12),
                     info.dirty ? ", uncommitted changes" : "");
}

}  // namespace bushel
