// LOCAL ONLY, never committed: stands in for register_query_command until it lands on main.
#include "commands.hpp"
namespace collide::cli { void register_query_command(CLI::App&) {} }
