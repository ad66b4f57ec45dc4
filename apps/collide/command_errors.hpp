#pragma once
// What every subcommand does with failure: input files checked before they are opened, output
// folders before the work is done, and every exception turned into exit status 2 with one line
// on stderr (never an abort).

#include <functional>
#include <string>

namespace collide::cli {

/// Runs the body of `collide COMMAND` and returns its exit status. Any exception becomes exit
/// status 2 and one line on stderr: "collide COMMAND: MESSAGE" for InvalidInput (whose message
/// names the file and field), "collide COMMAND: INPUT: out of memory" for std::bad_alloc,
/// "collide COMMAND: INPUT: WHAT" for any other std::exception. `input` names what the command
/// reads ("standard input", a file, a scene).
int run_guarded(const char* command, const std::string& input, const std::function<int()>& body) noexcept;

/// Throws InvalidInput "PATH: cannot be read (WHY)" unless `path` is a regular file that is not
/// empty: missing, a directory, a FIFO, a device (/dev/zero never ends, a FIFO without a writer
/// blocks the open forever) or an empty file is named instead of being opened.
void require_input_file(const std::string& path);

/// Throws InvalidInput "OPTION PATH: cannot be written (no folder 'DIR')" when the folder that
/// is to hold `path` does not exist or is not a folder, before any work is done for it.
void require_output_folder(const std::string& option, const std::string& path);

}  // namespace collide::cli
