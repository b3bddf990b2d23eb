// Output files are written completely or not at all: the text goes to NAME.tmp, which is renamed over
// NAME only once it has been written and closed without error.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <system_error>

namespace csim {

// A file or folder that could not be written, with the system's reason: what() is "PATH: FAILURE: REASON",
// e.g. "out/pile/paraview/contacts_000170.vtu: cannot write: No space left on device". A failure of the
// environment (a full disk, a quota, a folder without write permission), not of the scene: csim reports
// it as such (docs/contract.md).
struct FileWriteError : std::system_error {
  FileWriteError(const std::string& path, const std::string& failure, std::error_code reason)
      : std::system_error(reason, path + ": " + failure), path(path), failure(failure) {}
  // The same error with `path` under the folder `written` named under `shown` instead: a command writes in
  // a temporary folder that it removes when it fails, and must name the folder the user asked for.
  FileWriteError in_folder(const std::string& written, const std::string& shown) const;

  std::string path, failure;
};

// Throws FileWriteError naming the file when it cannot be written.
void write_file_atomically(const std::string& path, const std::string& contents);
// The same with the contents written by `write` to the file's stream, so that a large file need not be
// assembled in memory first.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace csim
