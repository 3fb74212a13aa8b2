#include "bushel/contact/contact_table.hpp"

#include <cmath>

#include "bushel/core/input_error.hpp"

namespace bushel {

void validate(const ContactParameters& p) {
  if (!(p.restitution > 0.0 && p.restitution <= 1.0)) {
    throw InputError("expected a coefficient of restitution in (0, 1], got " + std::to_string(p.restitution))
        .with_key("restitution");
  }
  if (!(p.static_friction >= 0.0) || !std::isfinite(p.static_friction)) {
    throw InputError("expected a static friction coefficient >= 0, got " + std::to_string(p.static_friction))
        .with_key("static_friction");
  }
  if (!(p.rolling_friction >= 0.0) || !std::isfinite(p.rolling_friction)) {
    throw InputError("expected a rolling friction coefficient >= 0, got " + std::to_string(p.rolling_friction))
        .with_key("rolling_friction");
  }
}

ContactTable::ContactTable(ContactParameters defaults) : defaults_(defaults) { validate(defaults_); }

ContactTable::Key ContactTable::key(const std::string& a, const std::string& b) {
  return a <= b ? Key{a, b} : Key{b, a};
}

void ContactTable::set(const std::string& a, const std::string& b, const ContactParameters& p) {
  try {
    validate(p);
  } catch (const InputError& e) {
    throw e.with_key(a + "-" + b);
  }
  pairs_[key(a, b)] = p;
}

const ContactParameters* ContactTable::find(const std::string& a, const std::string& b) const {
  if (a.empty() || b.empty()) return nullptr;
  const auto it = pairs_.find(key(a, b));
  return it == pairs_.end() ? nullptr : &it->second;
}

const ContactParameters& ContactTable::lookup(const Species& a, const Species& b) const {
  if (const auto* p = find(a.type, b.type)) return *p;
  const auto* ab = find(a.type, b.material);
  const auto* ba = find(a.material, b.type);
  if (ab && ba && !(*ab == *ba)) {
    throw InputError("contact parameters for '" + a.type + "'-'" + b.material + "' and '" + a.material + "'-'" +
                     b.type + "' both apply and differ; set '" + a.type + "'-'" + b.type + "' explicitly");
  }
  if (ab) return *ab;
  if (ba) return *ba;
  if (const auto* p = find(a.material, b.material)) return *p;
  return defaults_;
}

DenseContactTable ContactTable::resolve(std::span<const Species> species) const {
  const std::size_t n = species.size();
  std::vector<ContactParameters> entries(n * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) entries[i * n + j] = lookup(species[i], species[j]);
  }
  return {n, std::move(entries)};
}

}  // namespace bushel
