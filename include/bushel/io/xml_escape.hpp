#pragma once
// Text for XML and HTML (VTU files, the HTML report): the five characters with a meaning there
// replaced by their entities, so that user text (names, file names) can go into elements and
// quoted attributes.

#include <string>
#include <string_view>

namespace bushel::io {

/// `s` with & < > " ' as &amp; &lt; &gt; &quot; &apos;.
std::string xml_escaped(std::string_view s);

}  // namespace bushel::io
