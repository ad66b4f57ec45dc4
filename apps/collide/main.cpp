// The `collide` command-line tool: drives the library from the shell. Each subcommand is in its
// own file; see commands.hpp.
//
// Exit status: 0 done; 2 the command line, an input or an output is wrong (one line on stderr
// says which), or anything else failed (out of memory included: never an abort); 3 a
// command's independent check failed.

#include "commands.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <new>

namespace {

/// Exit status of an error: a command line CLI11 refuses (an unknown option, a value out of
/// range), output that cannot be written, an exception that no command caught.
constexpr int kErrorStatus = 2;

/// Standard output must have reached its file: `collide run > /dev/full` is an error, not a
/// summary silently lost.
int check_standard_output(int code) {
  if (std::fflush(stdout) == 0 && std::ferror(stdout) == 0) return code;
  std::fprintf(stderr, "collide: standard output could not be written\n");
  return code == 0 ? kErrorStatus : code;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    CLI::App app{"collide: collision detection for games (2D and 3D)", "collide"};
    app.set_version_flag("--version", "collide 0.1.0");
    app.require_subcommand(1);
    collide::cli::register_run_command(app);
    collide::cli::register_query_command(app);
    collide::cli::register_walk_command(app);
    collide::cli::register_cast_command(app);
    collide::cli::register_sdf_command(app);
    collide::cli::register_decompose_command(app);
    try {
      app.parse(argc, argv);
    } catch (const CLI::RuntimeError& e) {  // a command's own exit status; it said why
      return check_standard_output(e.get_exit_code());
    } catch (const CLI::ParseError& e) {
      const int code = app.exit(e);  // prints the help, the version or what is wrong
      return check_standard_output(code == 0 ? 0 : kErrorStatus);
    }
    return check_standard_output(0);
  } catch (const std::bad_alloc&) {
    std::fputs("collide: out of memory\n", stderr);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "collide: %s\n", e.what());
  } catch (...) {
    std::fputs("collide: failed (not a std::exception)\n", stderr);
  }
  return kErrorStatus;
}
