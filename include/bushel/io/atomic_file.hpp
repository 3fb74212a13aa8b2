#pragma once
// Output files that are either absent, the old version or the complete new one, never half
// written: a crash or a full disk during a long run must not leave a truncated result that
// looks valid.

#include <string>
#include <string_view>

namespace bushel::io {

/// Writes `content` to a temporary file in the directory of `path`, flushes it to disk, then
/// renames it over `path` (a rename within one directory is atomic on POSIX file systems).
/// Throws InputError naming the path if the file cannot be written; the temporary file is
/// removed then.
void write_file_atomically(const std::string& path, std::string_view content);

}  // namespace bushel::io
