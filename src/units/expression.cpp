#include "bushel/units/expression.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "bushel/core/input_error.hpp"

namespace bushel::units {
namespace {

bool name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_'; }
bool name_char(char c) { return name_start(c) || std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '.'; }

// Limits that keep a hostile or mistyped expression from exhausting the stack or overflowing
// an exponent: no scenario needs more than a few levels of parentheses or a unit to the 4th.
constexpr int max_depth = 64;              // nested parentheses, functions and unary minuses
constexpr int max_exponent = 32;           // of any base dimension, e.g. m^32
constexpr std::size_t max_length = 4096;   // characters of one expression
constexpr std::size_t quoted_length = 60;  // characters of it that an error message quotes

// The text as an error message quotes it: whole when short, else its start and "...".
std::string quoted(std::string_view text) {
  if (text.size() <= quoted_length) return std::string(text);
  return fmt::format("{}... ({} characters)", text.substr(0, quoted_length), text.size());
}

// A recursive-descent parser that evaluates as it goes.
class Parser {
 public:
  Parser(std::string_view text, const NameLookup& lookup) : s_(text), lookup_(lookup) {}

  Quantity run() {
    if (s_.size() > max_length) fail(fmt::format("longer than {} characters", max_length));
    const Quantity q = sum();
    skip();
    if (at_ < s_.size()) fail(fmt::format("unexpected '{}'", quoted(s_.substr(at_))));
    if (!std::isfinite(q.value)) fail("the result is not a finite number");
    return q;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(fmt::format("in the expression '{}': {}", quoted(s_), why));
  }
  // One level deeper into the grammar, for as long as the returned guard lives.
  struct Deeper {
    explicit Deeper(Parser& p) : p_(p) {
      if (++p_.depth_ > max_depth) p_.fail(fmt::format("nested more than {} levels deep", max_depth));
    }
    ~Deeper() { --p_.depth_; }
    Deeper(const Deeper&) = delete;
    Deeper& operator=(const Deeper&) = delete;
    Parser& p_;
  };
  Dimension times(Dimension a, Dimension b, int sign) const {
    const Dimension d{a.length + sign * b.length, a.mass + sign * b.mass, a.time + sign * b.time,
                      a.angle + sign * b.angle};
    for (const int e : {d.length, d.mass, d.time, d.angle}) {
      if (e > max_exponent || e < -max_exponent) fail(fmt::format("a unit to a power beyond {}", max_exponent));
    }
    return d;
  }
  void skip() {
    while (at_ < s_.size() && (s_[at_] == ' ' || s_[at_] == '\t')) ++at_;
  }
  bool eat(char c) {
    skip();
    if (at_ < s_.size() && s_[at_] == c) return ++at_, true;
    return false;
  }

  Quantity sum() {
    Quantity q = product();
    while (true) {
      const bool plus = eat('+');
      if (!plus && !eat('-')) return q;
      const Quantity r = product();
      if (r.dimension != q.dimension) {
        fail(fmt::format("cannot {} a {} and a {}", plus ? "add" : "subtract", dimension_name(q.dimension),
                         dimension_name(r.dimension)));
      }
      q.value += plus ? r.value : -r.value;
    }
  }

  Quantity product() {
    Quantity q = unary();
    while (true) {
      const bool mul = eat('*');
      if (!mul && !eat('/')) return q;
      const Quantity r = unary();
      if (!mul && r.value == 0.0) fail("division by zero");
      q.value = mul ? q.value * r.value : q.value / r.value;
      q.dimension = times(q.dimension, r.dimension, mul ? 1 : -1);
    }
  }

  Quantity unary() {
    if (eat('-')) {
      const Deeper guard(*this);
      Quantity q = unary();
      q.value = -q.value;
      return q;
    }
    return factor();
  }

  Quantity factor() {
    skip();
    if (at_ >= s_.size()) fail("it ends where a value was expected");
    if (eat('(')) {
      const Deeper guard(*this);
      const Quantity q = sum();
      if (!eat(')')) fail("a '(' without its ')'");
      return q;
    }
    const char c = s_[at_];
    if (std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '.') return number();
    if (!name_start(c)) fail(fmt::format("unexpected '{}'", quoted(s_.substr(at_))));
    const std::size_t start = at_;
    while (at_ < s_.size() && name_char(s_[at_])) ++at_;
    const std::string name(s_.substr(start, at_ - start));
    if (eat('(')) {
      const Deeper guard(*this);
      const Quantity arg = sum();
      if (!eat(')')) fail("a '(' without its ')'");
      return function(name, arg);
    }
    if (name == "pi") return {std::numbers::pi, dim::dimensionless};
    try {
      return lookup_(name);
    } catch (const InputError& e) {
      fail(e.problem());
    }
  }

  // A number and, if one follows, the longest unit symbol that does.
  Quantity number() {
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s_.data() + at_, s_.data() + s_.size(), v);
    if (ec != std::errc{}) fail(fmt::format("'{}' is not a number", quoted(s_.substr(at_))));
    at_ = static_cast<std::size_t>(end - s_.data());
    const std::size_t before = at_;
    skip();
    const Unit* best = nullptr;
    for (const Unit& u : known_units()) {
      if (s_.substr(at_).starts_with(u.symbol) && (!best || u.symbol.size() > best->symbol.size())) {
        const std::size_t after = at_ + u.symbol.size();
        if (after < s_.size() && name_char(s_[after]) && s_[after] != '.') continue;  // "m" of "mass"
        best = &u;
      }
    }
    if (!best) {
      at_ = before;
      return {v, dim::dimensionless};
    }
    at_ += best->symbol.size();
    return {v * best->factor, best->dimension};
  }

  Quantity function(const std::string& name, Quantity a) const {
    if (name == "sqrt") {
      const Dimension d = a.dimension;
      if (d.length % 2 != 0 || d.mass % 2 != 0 || d.time % 2 != 0 || d.angle % 2 != 0)
        fail("sqrt of a " + dimension_name(d) + " has no unit");
      if (a.value < 0.0) fail("sqrt of a negative number");
      return {std::sqrt(a.value), {d.length / 2, d.mass / 2, d.time / 2, d.angle / 2}};
    }
    if (name == "abs") return {std::abs(a.value), a.dimension};
    if (name == "sin" || name == "cos" || name == "tan") {
      if (a.dimension != dim::angle && a.dimension != dim::dimensionless)
        fail(name + " takes an angle, not a " + dimension_name(a.dimension));
      const double v = name == "sin" ? std::sin(a.value) : name == "cos" ? std::cos(a.value) : std::tan(a.value);
      return {v, dim::dimensionless};
    }
    fail("unknown function '" + name + "' (known: sqrt, abs, sin, cos, tan)");
  }

  std::string_view s_;
  const NameLookup& lookup_;
  std::size_t at_ = 0;
  int depth_ = 0;
};

}  // namespace

Quantity evaluate(std::string_view expression, const NameLookup& lookup) { return Parser(expression, lookup).run(); }

Quantity parse_quantity(std::string_view text) {
  const NameLookup none = [&](const std::string& name) -> Quantity {
    throw InputError("'" + name + "' is not a unit");
  };
  try {
    return evaluate(text, none);
  } catch (const InputError&) {
    throw InputError("expected a number with an optional unit, got '" + quoted(text) + "'");
  }
}

std::string_view si_symbol(Dimension d) {
  if (d == dim::dimensionless) return "";
  for (const Unit& u : known_units()) {
    if (u.factor == 1.0 && u.dimension == d) return u.symbol;
  }
  throw InputError("bushel has no unit for a " + dimension_name(d));
}

std::string format_si(const Quantity& q) {
  const std::string_view unit = si_symbol(q.dimension);
  return unit.empty() ? fmt::format("{:.12g}", q.value) : fmt::format("{:.12g} {}", q.value, unit);
}

}  // namespace bushel::units
