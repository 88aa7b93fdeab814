#pragma once
// Outputs are written whole or not at all: the content goes to a temporary file beside the
// target, is flushed, and is renamed over the target only when complete.

#include <filesystem>
#include <string_view>

namespace cwe {

// Writes `content` to `path` atomically (rename within the directory). Creates missing parent
// directories. Throws cwe::InputError naming the path when the file cannot be written; the
// target is then untouched.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

}  // namespace cwe
