#pragma once
// The registry of contact sub-models (each law is registered in this one table, so that adding one touches one file). Normal, damping and tangential
// laws are Hertz, EDEM's viscoelastic damping and Mindlin no-slip with history
// (docs/physics.md section 2); rolling laws are selectable. The pair loop is instantiated once
// per rolling model through std::visit, so no contact pays for a virtual call.

#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "bushel/contact/rolling_models.hpp"

namespace bushel {

/// The rolling models, by name: adding one is its struct (rolling_models.hpp) and a line here.
using RollingModel = std::variant<CdtRolling, EpsdRolling, LiggghtsCdtRolling, NoRolling>;

/// The model registered under `name` ("cdt", "epsd", "liggghts_cdt", "none"); throws InputError with the
/// known names and a did-you-mean.
RollingModel rolling_model(std::string_view name);
std::vector<std::string> rolling_model_names();
std::string_view name_of(const RollingModel& m);

/// History values a contact keeps: 3 for the tangential displacement plus the rolling model's.
int history_size(const RollingModel& m);

}  // namespace bushel
