// `collide query [FILE]`: reads questions from FILE or standard input, answers on standard output.

#include "commands.hpp"
#include "query.hpp"

#include <fstream>
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
    if (file->empty() || *file == "-") {
      answer_query_stream(std::cin, std::cout);
      return;
    }
    std::ifstream in(*file);
    if (!in) {
      std::cerr << "collide query: cannot read " << *file << "\n";
      throw CLI::RuntimeError(1);
    }
    answer_query_stream(in, std::cout);
  });
}

}  // namespace collide::cli
