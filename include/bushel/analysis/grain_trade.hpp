#pragma once
// The quantities the grain trade works in (docs/wheat.md, "Formulas the program offers users").
// All densities in kg/m3, volumes in m3, masses in kg.
//
// Two "packing ratios" appear in the literature, and both are offered under distinct names:
//  - packing_ratio(D_A, D_O): compaction in a bin, bulk density after packing over the
//    initial test weight (> 1 for compacted grain);
//  - tapped_packing_ratio(BD_t, rho_k): tapped bulk density over kernel apparent density,
//    a solid fraction (about 0.55-0.64 for wheat), as in kernel_size_fractions.csv.

#include <string>
#include <string_view>
#include <vector>

namespace bushel {

/// Packing ratio P = D_A / D_O [-]: packed bulk density over initial test weight.
double packing_ratio(double packed_density, double initial_density);
/// Compaction factor f_C = P - 1 [-].
double compaction_factor(double packing_ratio);
/// Mass in a bin M = D_O P V [kg].
double mass_in_bin(double initial_density, double packing_ratio, double volume);
/// Pack factor R = P D_O / D_s [-], D_s the standard test weight of the grain.
double pack_factor(double packing_ratio, double initial_density, double standard_test_weight);
/// Tapped packing ratio BD_t / rho_kernel [-] (experiment 4).
double tapped_packing_ratio(double tapped_density, double kernel_density);
/// Compressibility C = (BD_t - BD_l) / BD_t [-] (experiment 4).
double compressibility(double tapped_density, double loose_density);

/// A grain's standard bushel: the mass one bushel is reckoned at in trade (USDA).
struct StandardBushel {
  std::string grain;           ///< e.g. "wheat"
  double pounds = 0.0;         ///< lb per bushel
  double test_weight() const;  ///< the same as a density [kg/m3] (pounds lb per US bushel)
  double mass() const;         ///< [kg]
};

/// Standard bushels for wheat (60 lb), soybeans (60), corn (56), sorghum (56), rye (56),
/// barley (48) and oats (32).
const std::vector<StandardBushel>& standard_bushels();
/// Lookup by grain name; throws InputError listing the known grains (with a did-you-mean).
const StandardBushel& standard_bushel(std::string_view grain);

}  // namespace bushel
