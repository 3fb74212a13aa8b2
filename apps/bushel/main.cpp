// bushel: discrete element simulation of grain bulk density.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <exception>
#include <new>

#include "bushel/core/build_info.hpp"
#include "bushel/core/input_error.hpp"
#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"bushel: discrete element simulation of grain bulk density"};
  app.set_version_flag("--version", "bushel " + bushel::build_description());
  app.require_subcommand(1);
  bushel::cli::add_particle_command(app);
  bushel::cli::add_kernel_command(app);
  bushel::cli::add_verify_command(app);
  bushel::cli::add_demo_command(app);
  bushel::cli::add_bin_command(app);
  bushel::cli::add_doe_command(app);
  bushel::cli::add_calibrate_command(app);
  bushel::cli::add_run_command(app);
  bushel::cli::add_preview_command(app);
  bushel::cli::add_report_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, naming what was wrong, and where the options are listed.
    fmt::print(stderr, "bushel: error: {} (--help lists the commands and options)\n", e.what());
    return e.get_exit_code() != 0 ? e.get_exit_code() : 2;
  } catch (const bushel::InputError& e) {
    fmt::print(stderr, "bushel: error: {}\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "bushel: error: out of memory\n");
    return 70;
  } catch (const std::exception& e) {
    // A failure no check foresaw: still one line and an exit code, never an abort. It is a
    // bug: every bad input should be an InputError that says where it is.
    fmt::print(stderr, "bushel: internal error: {} (please report it with the command that led to it)\n", e.what());
    return 70;
  }
  return 0;
}
