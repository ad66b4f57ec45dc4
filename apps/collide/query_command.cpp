// `collide query [FILE]`: reads questions from FILE or standard input, answers on standard output.

#include "commands.hpp"
#include "query.hpp"

#include <iostream>
#include <memory>
#include <string>

namespace collide::cli {

void register_query_command(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "query", "Answer geometric questions given as JSON Lines (spec: shared/spec/query-jsonl.md)");
  cmd->add_option("file", *file, "Questions, one JSON object per line (default: standard input)");
  cmd->footer(query_ops_help());
  cmd->callback([file] {
    const int code = run_query(*file, std::cin, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace collide::cli
