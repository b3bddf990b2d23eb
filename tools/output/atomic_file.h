// Output files are written completely or not at all: the text goes to NAME.tmp, which is renamed over
// NAME only once it has been written and closed without error.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>

namespace csim {

// Throws std::runtime_error naming the file when it cannot be written.
void write_file_atomically(const std::string& path, const std::string& contents);
// The same with the contents written by `write` to the file's stream, so that a large file need not be
// assembled in memory first.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace csim
