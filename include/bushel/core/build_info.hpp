#pragma once
// The engine build a result came from. Every summary.json and checkpoint records it, so that
// results of different engine versions (a changed contact law, say) can be told apart, and a
// run continued by another build says so.

#include <string>
#include <string_view>

namespace bushel {

struct BuildInfo {
  std::string_view version;  ///< the release, as in CMakeLists.txt's project() ("0.1.0")
  std::string_view commit;   ///< the git commit built (40 hex digits), or "unknown" (no git, no archive)
  bool dirty = false;        ///< built from a tree with uncommitted changes to tracked files
};

/// This binary's build (generated at build time by cmake/BushelBuildInfo.cmake).
const BuildInfo& build_info();

/// One line naming a build: "0.1.0 (commit 0123456789ab)", with ", uncommitted changes" when
/// it was dirty. Two builds with the same description ran the same code (dirty ones aside).
std::string build_description(const BuildInfo& info = build_info());

}  // namespace bushel
