#include "bushel/contact/contact_model.hpp"

#include "bushel/core/did_you_mean.hpp"
#include "bushel/core/input_error.hpp"

namespace bushel {
namespace {

template <class... Models>
std::vector<RollingModel> all(std::variant<Models...>*) {
  return {Models{}...};
}

const std::vector<RollingModel>& registry() {
  static const std::vector<RollingModel> models = all(static_cast<RollingModel*>(nullptr));
  return models;
}

}  // namespace

std::string_view name_of(const RollingModel& m) {
  return std::visit([](const auto& model) { return std::string_view(model.name); }, m);
}

std::vector<std::string> rolling_model_names() {
  std::vector<std::string> names;
  for (const auto& m : registry()) names.emplace_back(name_of(m));
  return names;
}

RollingModel rolling_model(std::string_view name) {
  for (const auto& m : registry()) {
    if (name_of(m) == name) return m;
  }
  std::string list;
  for (const auto& n : rolling_model_names()) list += (list.empty() ? "" : ", ") + n;
  throw InputError("unknown rolling model '" + std::string(name) + "'" + did_you_mean(name, rolling_model_names()) +
                   "; known: " + list);
}

int history_size(const RollingModel& m) {
  return 3 + std::visit([](const auto& model) { return model.history_size; }, m);
}

}  // namespace bushel
