#include "bushel/analysis/grain_trade.hpp"

#include "bushel/core/did_you_mean.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/core/require.hpp"
#include "bushel/units/units.hpp"

namespace bushel {

double packing_ratio(double packed_density, double initial_density) {
  require_positive(packed_density, "packed_density", "830kg/m3", "kg/m3");
  require_positive(initial_density, "initial_density", "60lb/bu", "kg/m3");
  return packed_density / initial_density;
}

double compaction_factor(double packing_ratio) { return packing_ratio - 1.0; }

double mass_in_bin(double initial_density, double packing_ratio, double volume) {
  require_positive(initial_density, "initial_density", "60lb/bu", "kg/m3");
  require_positive(packing_ratio, "packing_ratio", "1.05");
  require_positive(volume, "volume", "480m3", "m3");
  return initial_density * packing_ratio * volume;
}

double pack_factor(double packing_ratio, double initial_density, double standard_test_weight) {
  require_positive(packing_ratio, "packing_ratio", "1.05");
  require_positive(initial_density, "initial_density", "60lb/bu", "kg/m3");
  require_positive(standard_test_weight, "standard_test_weight", "60lb/bu", "kg/m3");
  return packing_ratio * initial_density / standard_test_weight;
}

double tapped_packing_ratio(double tapped_density, double kernel_density) {
  require_positive(tapped_density, "tapped_density", "860kg/m3", "kg/m3");
  require_positive(kernel_density, "kernel_density", "1373kg/m3", "kg/m3");
  return tapped_density / kernel_density;
}

double compressibility(double tapped_density, double loose_density) {
  require_positive(tapped_density, "tapped_density", "860kg/m3", "kg/m3");
  require_positive(loose_density, "loose_density", "815kg/m3", "kg/m3");
  return (tapped_density - loose_density) / tapped_density;
}

double StandardBushel::test_weight() const { return units::from_unit(pounds, "lb/bu"); }
double StandardBushel::mass() const { return units::from_unit(pounds, "lb"); }

const std::vector<StandardBushel>& standard_bushels() {
  static const std::vector<StandardBushel> table = {
      {"wheat", 60}, {"soybeans", 60}, {"corn", 56}, {"sorghum", 56}, {"rye", 56}, {"barley", 48}, {"oats", 32},
  };
  return table;
}

const StandardBushel& standard_bushel(std::string_view grain) {
  std::vector<std::string> names;
  for (const auto& b : standard_bushels()) {
    if (b.grain == grain) return b;
    names.push_back(b.grain);
  }
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  throw InputError("unknown grain '" + std::string(grain) + "'" + did_you_mean(grain, names) + "; known: " + list);
}

}  // namespace bushel
