// The `collide` command-line tool: drives the library from the shell. Each subcommand is in its
// own file; see commands.hpp.

#include "commands.hpp"

#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
  CLI::App app{"collide: collision detection for games (2D and 3D)", "collide"};
  app.set_version_flag("--version", "collide 0.1.0");
  app.require_subcommand(1);
  collide::cli::register_run_command(app);
  collide::cli::register_query_command(app);
  collide::cli::register_walk_command(app);
  collide::cli::register_cast_command(app);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
