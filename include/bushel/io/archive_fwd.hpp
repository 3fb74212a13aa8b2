#pragma once
// The checkpoint archive's classes (binary_archive.hpp), declared for the headers of classes
// that save and load themselves.

namespace bushel::io {
class BinaryWriter;
class BinaryReader;
class SectionTable;
}  // namespace bushel::io
