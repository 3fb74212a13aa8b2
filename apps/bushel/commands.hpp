#pragma once
// Sub-commands of the bushel command line. Each registers its options on the app and runs
// when selected; errors surface as bushel::InputError and are reported by main().

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "bushel/units/units.hpp"

namespace bushel::cli {

void add_particle_command(CLI::App& app);
void add_kernel_command(CLI::App& app);
void add_verify_command(CLI::App& app);
void add_demo_command(CLI::App& app);
void add_bin_command(CLI::App& app);
void add_doe_command(CLI::App& app);
/// `calibrate`: Bayesian calibration, run by the Python package's driver.
void add_calibrate_command(CLI::App& app);
/// `report`: run folders as tables and plots.
void add_report_command(CLI::App& app);
/// `run` and `validate`: scenario files.
void add_run_command(CLI::App& app);
void add_preview_command(CLI::App& app);
/// `demo funnel`, registered on the `demo` sub-command.
void add_demo_funnel_command(CLI::App& demo);

/// Sets the OpenMP thread count (0 keeps the default).
void set_threads(int threads);

/// Parses a quantity given on the command line, naming the option in the error.
double option_quantity(const std::string& option, const std::string& text, units::Dimension expected);

/// The non-empty items of a `sep`-separated list ("a,b,c").
std::vector<std::string> split_list(const std::string& text, char sep = ',');

}  // namespace bushel::cli
