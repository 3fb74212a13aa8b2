#pragma once
// The one exception type for bad user input. It carries where the input came from (file,
// line, key) so that every layer can add what it knows and the message the user finally
// reads says exactly what was wrong, where, and what was expected.

#include <stdexcept>
#include <string>

namespace bushel {

class InputError : public std::runtime_error {
 public:
  /// `problem` says what is wrong and what was expected, with units where they apply.
  explicit InputError(std::string problem);

  /// Returns a copy with the source (a file path, "command line", ...) and line filled in
  /// where they were unknown; line 0 means "no line".
  [[nodiscard]] InputError at(const std::string& source, int line = 0) const;
  /// Returns a copy naming the key (a scenario path, a CSV column, a CLI option), prefixed
  /// to any key already set: with_key("materials") on "wheat.density" gives
  /// "materials.wheat.density".
  [[nodiscard]] InputError with_key(const std::string& key) const;

  const std::string& problem() const { return problem_; }
  const std::string& source() const { return source_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  InputError(std::string problem, std::string source, int line, std::string key);
  static std::string compose(const std::string& problem, const std::string& source, int line, const std::string& key);

  std::string problem_;
  std::string source_;
  int line_ = 0;
  std::string key_;
};

}  // namespace bushel
