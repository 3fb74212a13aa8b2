#pragma once
// Base64 (RFC 4648, with padding): binary data inside text, e.g. PNG figures embedded in an
// HTML report as data: URLs.

#include <string>
#include <string_view>

namespace bushel::io {

/// The base64 text of `bytes`.
std::string base64(std::string_view bytes);

}  // namespace bushel::io
