#include "cwe/io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "cwe/core/error.hpp"

namespace cwe {

AtomicFileWriter::AtomicFileWriter(std::filesystem::path path) : path_(std::move(path)) {
  std::error_code ec;
  if (path_.has_parent_path()) {
    std::filesystem::create_directories(path_.parent_path(), ec);
    if (ec) fail(ec.message());
  }
  temporary_ = path_.string() + ".tmp-" + std::to_string(static_cast<long>(::getpid()));
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (file_ == nullptr) fail(std::strerror(errno));
}

AtomicFileWriter::~AtomicFileWriter() {
  if (file_ == nullptr) return;
  std::fclose(file_);
  std::error_code ec;
  std::filesystem::remove(temporary_, ec);
}

void AtomicFileWriter::fail(const std::string& why) {
  if (file_ != nullptr) {
    std::fclose(file_);
    file_ = nullptr;
    std::error_code ec;
    std::filesystem::remove(temporary_, ec);
  }
  throw InputError(SourceLocation{path_.string()}, "cannot write the file: " + why);
}

void AtomicFileWriter::append(std::string_view text) {
  if (file_ == nullptr) fail("the file was already committed");
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size()) fail(std::strerror(errno));
}

void AtomicFileWriter::commit() {
  if (file_ == nullptr) fail("the file was already committed");
  const bool flushed = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  std::error_code ec;
  if (!flushed || !closed) {
    const std::string why = std::strerror(errno);
    std::filesystem::remove(temporary_, ec);
    fail(why);
  }
  std::filesystem::rename(temporary_, path_, ec);
  if (ec) {
    const std::string why = ec.message();
    std::filesystem::remove(temporary_, ec);
    fail(why);
  }
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  AtomicFileWriter writer(path);
  writer.append(content);
  writer.commit();
}

}  // namespace cwe
